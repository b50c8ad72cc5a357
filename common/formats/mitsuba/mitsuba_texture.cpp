// Mitsuba <texture> plugins → Texture (docs/scene-format.md, "Mitsuba 3 XML scenes"; common/formats/mitsuba/mitsuba_texture.h).
#include "common/formats/mitsuba/mitsuba_texture.h"

#include <algorithm>
#include <cmath>

#include "common/util/error.h"

namespace firstshot::mitsuba {
namespace {

/// The wrap mode @p name by Mitsuba's name (@p fallback when absent); zero and one (Mitsuba 0.6: black or white
/// outside [0, 1]) become clamp, noted.
TextureWrap wrapMode(Plugin& t, const char* name, TextureWrap fallback) {
  if (!t.has(name)) return fallback;
  const std::string w = t.string(name, "");
  if (w == "repeat") return TextureWrap::Repeat;
  if (w == "mirror") return TextureWrap::MirroredRepeat;
  if (w == "clamp") return TextureWrap::ClampToEdge;
  if (w == "zero" || w == "one") {
    t.doc().note("wrap zero", "bitmap wrap modes zero and one approximated by clamp (the edge texels continue outside "
                              "[0, 1] instead of black or white)");
    return TextureWrap::ClampToEdge;
  }
  t.doc().fail(t.take(name), "unknown wrap mode \"" + w + "\" (repeat, mirror, clamp, zero, one)");
}

/// Rec. 709 luminance of linear RGB, as Mitsuba reduces a colour texture to one value.
float luminance(const Color& c) { return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z; }

}  // namespace

std::shared_ptr<const Texture> mapTexels(const Texture& t, const std::function<Color(const Color&)>& f) {
  std::vector<Color> texels;
  texels.reserve(t.image->texels.size());
  for (const Color& c : t.image->texels) texels.push_back(f(c));
  auto out = std::make_shared<Texture>(t);
  out->image = std::make_shared<const TexelImage>(makeTexelImage(t.image->width, t.image->height, std::move(texels),
                                                                 t.image->name));
  return out;
}

TexturedColor TextureMapper::color(Plugin& p, const char* name, const Color& fallback) {
  if (const pugi::xml_node n = p.take(name)) {
    const pugi::xml_node target = doc_.resolve(n);
    const std::string type = target.attribute("type").value();
    if (std::string(target.name()) == "texture" && (type == "bitmap" || type == "checkerboard"))
      return {Color(1.0f), texture(target)};
  }
  return {p.color(name, fallback), nullptr};
}

double TextureMapper::scalar(Plugin& p, const char* name, double fallback) {
  const Color c = p.color(name, Color(float(fallback)));
  return (double(c.x) + c.y + c.z) / 3.0;
}

std::shared_ptr<const Texture> TextureMapper::texture(pugi::xml_node node) {
  std::shared_ptr<const Texture>& out = textures_[{node, 0}];
  if (out) return out;
  const Document::Nested nested(doc_, node);
  Plugin t(doc_, node);
  if (t.type() == "bitmap") {
    out = bitmap(t);
  } else if (t.type() == "checkerboard") {
    out = checkerboard(t);
  } else {
    doc_.fail(node, "texture type \"" + t.type() + "\" is not supported (bitmap, checkerboard)");
  }
  t.finish();
  return out;
}

std::shared_ptr<const Texture> TextureMapper::opacity(pugi::xml_node node) {
  std::shared_ptr<const Texture>& out = textures_[{node, 1}];
  if (out) return out;
  const std::shared_ptr<const Texture> colour = texture(node);
  TexelImage im = *colour->image;
  im.alpha.resize(im.texels.size());
  for (size_t i = 0; i < im.texels.size(); ++i) im.alpha[i] = std::clamp(luminance(im.texels[i]), 0.0f, 1.0f);
  auto t = std::make_shared<Texture>(*colour);
  t->image = std::make_shared<const TexelImage>(std::move(im));
  return out = t;
}

std::shared_ptr<const Texture> TextureMapper::bitmap(Plugin& t) {
  const std::string name = t.string("filename", "");
  if (name.empty()) doc_.fail(t.node(), "a bitmap needs <string name=\"filename\" value=…>");
  const std::filesystem::path path = resolve_(name);
  // Decoding, whatever the texture is used for: sRGB for 8- and 16-bit data, float data as stored (what
  // readTexelImage does, and Mitsuba's default); Mitsuba 3's raw reads integers as stored too; Mitsuba 0.6's gamma
  // overrides it: −1 sRGB, 1 linear, another γ the power law v^γ.
  bool srgb = !t.boolean("raw", false);
  double gamma = 0;
  if (t.has("gamma")) {
    gamma = t.number("gamma", 0);
    if (gamma == -1 || gamma == 1) {
      srgb = gamma == -1, gamma = 0;
    } else if (!(gamma > 0)) {
      doc_.fail(t.take("gamma"), "gamma must be −1 (sRGB), 1 (linear) or a positive exponent");
    }
  }
  const std::string key = path.string() + (gamma > 0 ? "\ngamma " + std::to_string(gamma) : srgb ? "" : "\nlinear");
  std::shared_ptr<const TexelImage>& image = images_[key];
  if (!image) {
    try {
      TexelImage im = readTexelImage(path.string(), srgb && gamma == 0);
      if (gamma > 0) {  // stored values v, linear v^γ
        for (Color& c : im.texels) c = glm::pow(glm::max(c, Color(0.0f)), Color(float(gamma)));
        std::vector<float> alpha = std::move(im.alpha);
        im = makeTexelImage(im.width, im.height, std::move(im.texels), im.name);
        im.alpha = std::move(alpha);
      }
      image = std::make_shared<const TexelImage>(std::move(im));
    } catch (const InputError& e) {
      doc_.fail(t.node(), e.what());
    }
  }
  auto texture = std::make_shared<Texture>();
  texture->image = image;
  const std::string filter = t.string("filter_type", "bilinear");
  if (filter == "nearest") {
    texture->filter = TextureFilter::Nearest;
  } else if (filter == "ewa" || filter == "trilinear") {
    doc_.note("filter " + filter, "bitmap filter_type " + filter + " approximated by bilinear lookups in the full "
                                  "image (no MIP maps: a pixel's samples average the texture under it)");
  } else if (filter != "bilinear") {
    doc_.fail(t.take("filter_type"), "unknown filter_type \"" + filter + "\" (bilinear, nearest; ewa, trilinear)");
  }
  const TextureWrap wrap = wrapMode(t, "wrap_mode", TextureWrap::Repeat);
  texture->wrapU = wrapMode(t, "wrap_mode_u", wrap);  // Mitsuba 0.6 may give the two axes apart
  texture->wrapV = wrapMode(t, "wrap_mode_v", wrap);
  texture->transform = uvTransform(t);
  return texture;
}

std::shared_ptr<const Texture> TextureMapper::checkerboard(Plugin& t) {
  // Mitsuba's checkerboard: color0 where u and v fall in the same half of [0, 1) (both below ½ or both above),
  // color1 elsewhere, repeated; exactly a 2 × 2 image looked up nearest.
  const Color c0 = t.color("color0", Color(0.4f)), c1 = t.color("color1", Color(0.2f));
  auto texture = std::make_shared<Texture>();
  texture->image = std::make_shared<const TexelImage>(makeTexelImage(2, 2, {c0, c1, c1, c0}, doc_.path(t.node())));
  texture->filter = TextureFilter::Nearest;
  texture->transform = uvTransform(t);
  return texture;
}

TextureTransform TextureMapper::uvTransform(Plugin& t) {
  TextureTransform tr;
  const bool scaled = t.has("uscale") || t.has("vscale") || t.has("uoffset") || t.has("voffset");
  if (!t.has("to_uv")) {  // Mitsuba 0.6: uv' = uv ⊙ (uscale, vscale) + (uoffset, voffset)
    tr.scale = Vec2(float(t.number("uscale", 1)), float(t.number("vscale", 1)));
    tr.offset = Vec2(float(t.number("uoffset", 0)), float(t.number("voffset", 0)));
    return tr;
  }
  if (scaled) doc_.fail(t.take("to_uv"), "give either to_uv or uscale, vscale, uoffset, voffset");
  // to_uv's x, y part and translation (its z row and column are ignored, as Mitsuba does) as offset + R · S: the
  // columns of the 2 × 2 part must be orthogonal (a rotation times a scale along u and v; no shear).
  const Mat4d m = t.transform("to_uv");
  const Vec2d c0(m[0][0], m[0][1]), c1(m[1][0], m[1][1]);
  const double sx = glm::length(c0);
  if (!(sx > 0) || std::abs(glm::dot(c0, c1)) > 1e-9 * sx * glm::length(c1) || c0.x * c1.y - c0.y * c1.x == 0)
    doc_.fail(t.take("to_uv"), "to_uv must be a rotation, scale and translation of u and v (no shear, not singular)");
  const double c = c0.x / sx, s = -c0.y / sx;  // TextureTransform's rotation matrix is [c s; −s c]
  tr.rotation = float(std::atan2(s, c));
  tr.scale = Vec2(float(sx), float(glm::dot(c1, Vec2d(s, c))));
  tr.offset = Vec2(float(m[3][0]), float(m[3][1]));
  return tr;
}

}  // namespace firstshot::mitsuba
