// Mitsuba 3 XML documents: parsing, $parameters, ids, element paths with lines, typed properties.
#include "common/formats/mitsuba/mitsuba_xml.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <functional>

#include <glm/gtc/matrix_transform.hpp>

#include "common/color/spectrum_rgb.h"
#include "common/util/error.h"

namespace firstshot::mitsuba {
namespace {

bool equalsIgnoringCase(const std::string& a, const char* b) {
  return std::equal(a.begin(), a.end(), b, b + std::char_traits<char>::length(b),
                    [](char x, char y) { return std::tolower((unsigned char)x) == std::tolower((unsigned char)y); });
}

/// Every element below @p root, depth first in document order (a loop, not recursion: any nesting depth).
void forEachElement(pugi::xml_node root, const std::function<void(pugi::xml_node)>& f) {
  pugi::xml_node n = root.first_child();
  while (n) {
    if (n.type() == pugi::node_element) f(n);
    if (n.first_child()) {
      n = n.first_child();
      continue;
    }
    while (n != root && !n.next_sibling()) n = n.parent();
    n = n == root ? pugi::xml_node() : n.next_sibling();
  }
}

constexpr int kMaxNesting = 16;   ///< bsdfs and textures inside one another (a <ref> cycle ends here)
constexpr size_t kMaxPathParts = 12;  ///< element path components shown in messages (deeper: the middle elided)

/// A vector given as attribute "value" (3 numbers) or as attributes x, y, z (each defaulting to @p fallback's).
Vec3d vectorAttributes(const Document& doc, pugi::xml_node node, const Vec3d& fallback) {
  if (node.attribute("value")) {
    const auto v = numbers(doc, node, "value", 3);
    return {v[0], v[1], v[2]};
  }
  Vec3d r = fallback;
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (node.attribute(axes[i])) r[i] = numbers(doc, node, axes[i], 1)[0];
  return r;
}

Vec3d vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

/// Mitsuba's lookat: local +z towards the target, +y up, +x = up × forward (the image's left).
Mat4d lookAt(const Document& doc, pugi::xml_node op) {
  const Vec3d origin = vec3(numbers(doc, op, "origin", 3)), target = vec3(numbers(doc, op, "target", 3));
  const Vec3d up = op.attribute("up") ? vec3(numbers(doc, op, "up", 3)) : Vec3d(0, 1, 0);
  if (!(glm::length(target - origin) > 0)) doc.fail(op, "origin and target coincide");
  const Vec3d dir = glm::normalize(target - origin);
  if (!(glm::length(glm::cross(up, dir)) > 0)) doc.fail(op, "up is zero or parallel to the viewing direction");
  const Vec3d left = glm::normalize(glm::cross(up, dir));
  Mat4d m(1.0);
  m[0] = glm::dvec4(left, 0), m[1] = glm::dvec4(glm::cross(dir, left), 0), m[2] = glm::dvec4(dir, 0);
  m[3] = glm::dvec4(origin, 1);
  return m;
}

/// One operation of a <transform>.
Mat4d transformOperation(const Document& doc, pugi::xml_node op) {
  const std::string tag = op.name();
  if (tag == "translate") return glm::translate(Mat4d(1.0), vectorAttributes(doc, op, Vec3d(0.0)));
  if (tag == "rotate") {
    const Vec3d axis = vectorAttributes(doc, op, Vec3d(0.0));
    if (!(glm::length(axis) > 0)) doc.fail(op, "rotation axis is zero");
    return glm::rotate(Mat4d(1.0), glm::radians(numbers(doc, op, "angle", 1)[0]), glm::normalize(axis));
  }
  if (tag == "scale") {
    Vec3d s(1.0);
    if (op.attribute("value")) {
      const auto v = numbers(doc, op, "value");
      if (v.size() != 1 && v.size() != 3) doc.fail(op, "expected 1 or 3 numbers");
      s = v.size() == 1 ? Vec3d(v[0]) : vec3(v);
    } else {
      s = vectorAttributes(doc, op, Vec3d(1.0));
    }
    if (s.x == 0 || s.y == 0 || s.z == 0) doc.fail(op, "scale must not be zero");
    return glm::scale(Mat4d(1.0), s);
  }
  if (tag == "matrix") {
    const auto v = numbers(doc, op, "value");
    const int n = v.size() == 16 ? 4 : v.size() == 9 ? 3 : 0;
    if (n == 0) doc.fail(op, "expected 16 (or 9) numbers, row-major");
    Mat4d m(1.0);
    for (int row = 0; row < n; ++row)
      for (int col = 0; col < n; ++col) m[col][row] = v[size_t(row * n + col)];
    return m;
  }
  if (tag == "lookat") return lookAt(doc, op);
  doc.fail(op, "unknown transform operation <" + tag + "> (translate, rotate, scale, matrix, lookat)");
}

}  // namespace

std::vector<double> numbers(const Document& doc, pugi::xml_node node, const char* attr, size_t count) {
  const pugi::xml_attribute a = node.attribute(attr);
  if (!a) doc.fail(node, std::string("missing attribute \"") + attr + "\"");
  const std::string text = a.value();
  std::vector<double> out;
  size_t i = 0;
  while (i < text.size()) {
    if (text[i] == ',' || std::isspace((unsigned char)text[i])) {
      ++i;
      continue;
    }
    size_t end = i;
    while (end < text.size() && text[end] != ',' && !std::isspace((unsigned char)text[end])) ++end;
    double v = 0;
    const auto r = std::from_chars(text.data() + i, text.data() + end, v);
    if (r.ec != std::errc() || r.ptr != text.data() + end)
      doc.fail(node, std::string("attribute \"") + attr + "\": not a number: \"" + text.substr(i, end - i) + "\"");
    if (!std::isfinite(v)) doc.fail(node, std::string("attribute \"") + attr + "\": not finite");
    out.push_back(v);
    i = end;
  }
  if (out.empty() || (count > 0 && out.size() != count))
    doc.fail(node, std::string("attribute \"") + attr + "\": expected " + (count > 0 ? std::to_string(count) : "some") +
                       " number" + (count == 1 ? "" : "s") + ", got \"" + text + "\"");
  return out;
}

std::string elementName(const Document& doc, pugi::xml_node node) {
  const std::string p = doc.path(node);
  return node.attribute("id") ? p + " (\"" + node.attribute("id").value() + "\")" : p;
}

Document::Document(std::string file, const std::string& text) : file_(std::move(file)) {
  lineStarts_.push_back(0);
  for (size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') lineStarts_.push_back(i + 1);
  const pugi::xml_parse_result r = doc_.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!r) {
    const size_t offset = size_t(std::max<ptrdiff_t>(r.offset, 0));
    const size_t l = size_t(std::upper_bound(lineStarts_.begin(), lineStarts_.end(), offset) - lineStarts_.begin());
    throw InputError(file_, "line " + std::to_string(l) + ", column " + std::to_string(offset - lineStarts_[l - 1] + 1),
                     std::string("malformed XML: ") + r.description());
  }
  const pugi::xml_node s = scene();
  if (!s || doc_.document_element() != s) throw InputError(file_, "", "not a Mitsuba scene (the root element is not <scene>)");
  if (!s.attribute("version")) fail(s, "missing attribute \"version\" (e.g. version=\"3.0.0\")");
  const std::string version = s.attribute("version").value();
  int major = 0;
  if (std::from_chars(version.data(), version.data() + version.size(), major).ec != std::errc())
    fail(s, "version \"" + version + "\" is not a version number");
  if (major < 2) {
    upgradeNames();
    note("version", "Mitsuba " + version + " scene: property names upgraded to snake_case as Mitsuba 3 does");
  }
  substitute();
  std::map<std::pair<const void*, std::string>, int> seen;  // per parent and tag: elements so far
  forEachElement(s, [&](pugi::xml_node n) {
    index_[n.internal_object()] = ++seen[{n.parent().internal_object(), n.name()}];
  });
  forEachElement(s, [&](pugi::xml_node n) {
    if (!n.attribute("id") || std::string(n.name()) == "ref") return;
    if (!ids_.emplace(n.attribute("id").value(), n).second)
      fail(n, std::string("id \"") + n.attribute("id").value() + "\" is used twice");
  });
}

void Document::upgradeNames() {
  forEachElement(scene(), [](pugi::xml_node n) {
    pugi::xml_attribute a = n.attribute("name");
    if (!a || n.name() == std::string("default")) return;
    std::string name = a.value();
    for (size_t i = 0; i + 1 < name.size(); ++i) {  // the rule of Mitsuba 3's upgrade_tree
      if (std::islower((unsigned char)name[i]) && std::isupper((unsigned char)name[i + 1])) {
        name.insert(i + 1, "_");
        i += 2;
        while (i < name.size() && std::isupper((unsigned char)name[i])) ++i;
      }
    }
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    a.set_value(name.c_str());
  });
}

void Document::substitute() {
  std::map<std::string, std::string> params;
  for (pugi::xml_node d : scene().children("default")) {
    if (!d.attribute("name") || !d.attribute("value")) fail(d, "a <default> needs \"name\" and \"value\"");
    params[d.attribute("name").value()] = d.attribute("value").value();
  }
  forEachElement(scene(), [&](pugi::xml_node n) {
    for (pugi::xml_attribute a : n.attributes()) {
      const std::string v = a.value();
      if (v.find('$') == std::string::npos) continue;
      std::string out;
      for (size_t i = 0; i < v.size();) {
        size_t end = i + 1;
        while (v[i] == '$' && end < v.size() && (std::isalnum((unsigned char)v[end]) || v[end] == '_')) ++end;
        if (v[i] != '$' || end == i + 1) {
          out += v[i++];
          continue;
        }
        const std::string name = v.substr(i + 1, end - i - 1);
        const auto it = params.find(name);
        if (it == params.end()) fail(n, "undefined parameter $" + name + " (no <default name=\"" + name + "\" value=…>)");
        out += it->second;
        i = end;
      }
      a.set_value(out.c_str());
    }
  });
}

int Document::line(pugi::xml_node node) const {
  const ptrdiff_t offset = node.offset_debug();
  if (offset < 0) return 0;
  return int(std::upper_bound(lineStarts_.begin(), lineStarts_.end(), size_t(offset)) - lineStarts_.begin());
}

std::string Document::path(pugi::xml_node node) const {
  std::vector<std::string> parts;  // innermost first
  for (pugi::xml_node n = node; n && n.type() == pugi::node_element; n = n.parent()) {
    if (n.attribute("name") && n.parent() != doc_) {
      parts.push_back(n.attribute("name").value());
      continue;
    }
    const auto it = index_.find(n.internal_object());
    const int index = it == index_.end() ? 1 : it->second;
    const bool repeated = index > 1 || n.next_sibling(n.name());
    parts.push_back(repeated ? std::string(n.name()) + "[" + std::to_string(index) + "]" : std::string(n.name()));
  }
  if (parts.size() > kMaxPathParts)  // keep the outermost 4 and the innermost 7
    parts.erase(parts.begin() + 7, parts.end() - 4), parts.insert(parts.begin() + 7, "…");
  std::string p;
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) p += (p.empty() ? "" : "/") + *it;
  return p;
}

Document::Nested::Nested(Document& doc, pugi::xml_node node) : doc_(doc) {
  if (++doc_.nesting_ > kMaxNesting) {
    --doc_.nesting_;
    doc_.fail(node, "bsdfs or textures nested more than " + std::to_string(kMaxNesting) + " deep (a <ref> cycle?)");
  }
}

std::string Document::where(pugi::xml_node node) const {
  if (!node) return "";
  std::string id = node.attribute("id") ? std::string("id \"") + node.attribute("id").value() + "\", " : "";
  const int l = line(node);
  return path(node) + " (" + id + (l > 0 ? "line " + std::to_string(l) : "") + ")";
}

void Document::fail(pugi::xml_node node, const std::string& message) const { throw InputError(file_, where(node), message); }

pugi::xml_node Document::byId(const std::string& id) const {
  const auto it = ids_.find(id);
  return it == ids_.end() ? pugi::xml_node() : it->second;
}

pugi::xml_node Document::resolve(pugi::xml_node node) const {
  if (std::string(node.name()) != "ref") return node;
  const pugi::xml_node target = byId(node.attribute("id").value());
  if (!target) fail(node, std::string("no element has id \"") + node.attribute("id").value() + "\"");
  return target;
}

void Document::note(const std::string& key, const std::string& message) {
  if (noted_.insert(key).second) notes_.push_back(message);
}

void Document::flush() {
  for (const std::string& n : notes_) std::fprintf(stderr, "%s: %s\n", file_.c_str(), n.c_str());
  notes_.clear();
  if (ignored_.empty()) return;
  std::string list;
  for (size_t i = 0; i < std::min<size_t>(ignored_.size(), 4); ++i) list += (i ? ", " : "") + ignored_[i];
  std::fprintf(stderr, "%s: %zu propert%s not used by firstshot, skipped (%s%s)\n", file_.c_str(), ignored_.size(),
               ignored_.size() == 1 ? "y" : "ies", list.c_str(), ignored_.size() > 4 ? ", …" : "");
  ignored_.clear();
}

Plugin::Plugin(Document& doc, pugi::xml_node node) : doc_(doc), node_(node), type_(node.attribute("type").value()) {
  if (type_.empty()) doc.fail(node, std::string("<") + node.name() + "> without a \"type\" attribute");
  for (pugi::xml_node c : node.children()) {
    if (c.type() != pugi::node_element) continue;
    if (!c.attribute("name")) {
      unnamed_.push_back(c);
    } else if (!named_.emplace(c.attribute("name").value(), c).second) {
      doc.fail(c, std::string("property \"") + c.attribute("name").value() + "\" is given twice");
    }
  }
}

void Plugin::finish() {
  for (const auto& [name, node] : named_)
    if (!readNamed_.count(name)) doc_.ignore(node);
  for (size_t i = 0; i < unnamed_.size(); ++i)
    if (!readUnnamed_.count(i)) doc_.ignore(unnamed_[i]);
}

pugi::xml_node Plugin::take(const char* name) {
  const auto it = named_.find(name);
  if (it == named_.end()) return {};
  readNamed_.insert(name);
  return it->second;
}

std::vector<pugi::xml_node> Plugin::nested(const char* tag) {
  std::vector<pugi::xml_node> out;
  for (size_t i = 0; i < unnamed_.size(); ++i) {
    const pugi::xml_node target = doc_.resolve(unnamed_[i]);
    if (std::string(target.name()) != tag) continue;
    readUnnamed_.insert(i);
    out.push_back(target);
  }
  return out;
}

namespace {
/// @throws InputError unless @p node is one of the tags in @p tags.
void expectTag(const Document& doc, pugi::xml_node node, std::initializer_list<const char*> tags) {
  std::string list;
  for (const char* t : tags) {
    if (node.name() == std::string(t)) return;
    list += std::string(list.empty() ? "" : " or ") + "<" + t + ">";
  }
  doc.fail(node, "expected " + list + ", got <" + node.name() + ">");
}
}  // namespace

double Plugin::number(const char* name, double fallback) {
  const pugi::xml_node n = take(name);
  if (!n) return fallback;
  expectTag(doc_, n, {"float", "integer"});
  return numbers(doc_, n, "value", 1)[0];
}

int Plugin::integer(const char* name, int fallback) {
  const pugi::xml_node n = take(name);
  if (!n) return fallback;
  expectTag(doc_, n, {"integer"});
  std::string v = n.attribute("value").value();
  v.erase(0, v.find_first_not_of(" \t\r\n"));
  v.erase(v.find_last_not_of(" \t\r\n") + 1);
  int out = 0;
  const auto r = std::from_chars(v.data(), v.data() + v.size(), out);
  if (v.empty() || r.ec != std::errc() || r.ptr != v.data() + v.size()) doc_.fail(n, "not an integer: \"" + v + "\"");
  return out;
}

bool Plugin::boolean(const char* name, bool fallback) {
  const pugi::xml_node n = take(name);
  if (!n) return fallback;
  expectTag(doc_, n, {"boolean"});
  const std::string v = n.attribute("value").value();
  if (equalsIgnoringCase(v, "true")) return true;
  if (equalsIgnoringCase(v, "false")) return false;
  doc_.fail(n, "expected true or false, got \"" + v + "\"");
}

std::string Plugin::string(const char* name, const std::string& fallback) {
  const pugi::xml_node n = take(name);
  if (!n) return fallback;
  expectTag(doc_, n, {"string"});
  if (!n.attribute("value")) doc_.fail(n, "missing attribute \"value\"");
  return n.attribute("value").value();
}

Vec3d Plugin::point(const char* name, const Vec3d& fallback) {
  const pugi::xml_node n = take(name);
  if (!n) return fallback;
  expectTag(doc_, n, {"point", "vector"});
  return vectorAttributes(doc_, n, Vec3d(0.0));
}

Color Plugin::color(const char* name, const Color& fallback) {
  const pugi::xml_node n = take(name);
  return n ? colorOf(n) : fallback;
}

Color Plugin::colorOf(pugi::xml_node ref) {
  const pugi::xml_node n = doc_.resolve(ref);
  const std::string tag = n.name();
  Color c(0.0f);
  if (tag == "texture") {
    const Document::Nested nested(doc_, n);
    Plugin t(doc_, n);
    if (t.type() == "bitmap" && doc_.bitmapMean_) {
      doc_.note("bitmap mean", "bitmap textures where firstshot takes a constant (a roughness, a weight, a conductor's "
                               "or glass's tint, a radiance) replaced by their image's mean");
      return doc_.bitmapMean_(n);
    }
    if (t.type() == "bitmap") {
      doc_.note("bitmap", "bitmap textures approximated by 0.5 grey (the image is not read)");
      t.string("filename", "");
      return Color(0.5f);
    }
    if (t.type() != "checkerboard")
      doc_.fail(n, "texture type \"" + t.type() + "\" is not supported (bitmap, checkerboard)");
    doc_.note("checkerboard", "checkerboard textures approximated by the mean of their two colours");
    c = 0.5f * (t.color("color0", Color(0.4f)) + t.color("color1", Color(0.2f)));
    t.finish();
    return c;
  }
  expectTag(doc_, n, {"rgb", "srgb", "spectrum", "blackbody", "float"});
  if (tag == "spectrum" || tag == "blackbody") return spectrumColor(n);
  if (tag == "srgb") return srgbColor(n);
  const auto v = numbers(doc_, n, "value");
  if (v.size() == 1) {
    c = Color(float(v[0]));
  } else if (v.size() == 3 && tag == "rgb") {
    c = Color(float(v[0]), float(v[1]), float(v[2]));
  } else {
    doc_.fail(n, tag == "rgb" ? "expected 3 numbers (or one for grey)" : "expected one number");
  }
  if (glm::any(glm::lessThan(c, Color(0.0f)))) doc_.fail(n, "must not be negative");
  return c;
}

Color Plugin::srgbColor(pugi::xml_node n) {
  std::vector<double> v;
  const std::string text = n.attribute("value").value();
  if (!text.empty() && text[0] == '#') {  // "#rrggbb"
    unsigned rgb = 0;
    char tail = 0;
    if (text.size() != 7 || std::sscanf(text.c_str() + 1, "%6x%c", &rgb, &tail) != 1)
      doc_.fail(n, "expected \"#rrggbb\" or 3 numbers in [0, 1], got \"" + text + "\"");
    v = {((rgb >> 16) & 255) / 255.0, ((rgb >> 8) & 255) / 255.0, (rgb & 255) / 255.0};
  } else {
    v = numbers(doc_, n, "value");
    if (v.size() == 1) v = {v[0], v[0], v[0]};
    if (v.size() != 3) doc_.fail(n, "expected 3 numbers (or one for grey)");
  }
  for (double x : v)
    if (!(x >= 0)) doc_.fail(n, "must not be negative");
  return Color(float(srgbToLinear(v[0])), float(srgbToLinear(v[1])), float(srgbToLinear(v[2])));
}

Color Plugin::spectrumColor(pugi::xml_node n) {
  const bool emission = std::string(node_.name()) == "emitter";  // a radiance or an intensity, else a reflectance
  const std::string tag = n.name();
  if (tag == "blackbody" || n.attribute("type")) {  // Mitsuba 0.6's <blackbody temperature="…K" scale="…"/>, or 3's
    double kelvin = 0, scale = 1;
    if (tag == "blackbody") {
      std::string t = n.attribute("temperature").value();
      if (!t.empty() && (t.back() == 'K' || t.back() == 'k')) t.pop_back();
      char* end = nullptr;
      kelvin = std::strtod(t.c_str(), &end);
      if (t.empty() || *end != '\0') doc_.fail(n, "expected temperature=\"…K\"");
      if (n.attribute("scale")) scale = numbers(doc_, n, "scale", 1)[0];
    } else {
      Plugin p(doc_, n);
      if (p.type() != "blackbody")
        doc_.fail(n, "spectrum type \"" + p.type() + "\" is not supported (blackbody; or a value list)");
      kelvin = p.number("temperature", 0), scale = p.number("scale", 1);
      p.finish();
    }
    if (!(kelvin > 0 && kelvin < 1e6)) doc_.fail(n, "the temperature must be in (0, 10⁶) kelvin");
    if (!(scale >= 0)) doc_.fail(n, "scale must not be negative");
    doc_.note("blackbody", "blackbody spectra: Planck radiance, W/(m² sr nm), to linear sRGB by the CIE 1931 observer "
                           "(luminance = its mean over ȳ, the scale of Mitsuba's RGB renderer)");
    return emissionRgb([&](double nm) { return planckRadiance(nm, kelvin); }) * float(scale);
  }
  if (n.attribute("filename")) doc_.fail(n, "spectrum files are not supported (give the wavelength:value list)");
  const std::string text = n.attribute("value").value();
  if (text.find(':') == std::string::npos) {
    const auto v = numbers(doc_, n, "value");
    if (v.size() != 1) doc_.fail(n, "expected one number (grey) or wavelength:value pairs");
    if (v[0] < 0) doc_.fail(n, "must not be negative");
    return Color(float(v[0]));
  }
  SampledSpectrum s;
  size_t i = 0;
  while (i < text.size()) {  // "λ:v" pairs separated by commas and/or white space
    if (text[i] == ',' || std::isspace((unsigned char)text[i])) {
      ++i;
      continue;
    }
    size_t end = i;
    while (end < text.size() && text[end] != ',' && !std::isspace((unsigned char)text[end])) ++end;
    const std::string pair = text.substr(i, end - i);
    const size_t colon = pair.find(':');
    double nm = 0, v = 0;
    const auto a = std::from_chars(pair.data(), pair.data() + colon, nm);
    const auto b = colon == std::string::npos ? a : std::from_chars(pair.data() + colon + 1, pair.data() + pair.size(), v);
    if (colon == std::string::npos || a.ec != std::errc() || a.ptr != pair.data() + colon || b.ec != std::errc() ||
        b.ptr != pair.data() + pair.size() || !std::isfinite(nm) || !std::isfinite(v))
      doc_.fail(n, "expected wavelength:value pairs (nm:value), got \"" + pair + "\"");
    if (!s.nm.empty() && !(nm > s.nm.back())) doc_.fail(n, "wavelengths must increase (\"" + pair + "\")");
    if (v < 0) doc_.fail(n, "must not be negative (\"" + pair + "\")");
    s.nm.push_back(nm), s.value.push_back(v);
    i = end;
  }
  doc_.note(emission ? "spectrum emission" : "spectrum reflectance",
            emission ? "emission spectra (nm:value) to linear sRGB by the CIE 1931 observer, luminance = their mean "
                       "over ȳ (Mitsuba's RGB scale)"
                     : "reflectance spectra (nm:value) to linear sRGB by the CIE 1931 observer under D65 (a flat "
                       "spectrum is grey; Mitsuba 0.6's RGB mode makes it (1.2, 0.95, 0.91))");
  return emission ? emissionRgb([&](double nm) { return s.at(nm); }) : reflectanceRgb(s);
}

Mat4d Plugin::transform(const char* name) {
  const pugi::xml_node n = take(name);
  Mat4d m(1.0);
  if (!n) return m;
  expectTag(doc_, n, {"transform"});
  for (pugi::xml_node op : n.children())
    if (op.type() == pugi::node_element) m = transformOperation(doc_, op) * m;
  return m;
}

}  // namespace firstshot::mitsuba
