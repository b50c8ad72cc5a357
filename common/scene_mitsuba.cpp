// Mitsuba 3 XML scenes → SceneDesc: the scene's elements, shapes, emitters and the sensor
// (docs/scene-format.md, "Mitsuba 3 XML scenes"); bsdfs in mitsuba_bsdf.cpp, XML in mitsuba_xml.cpp.
#include "common/scene_mitsuba.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/lights.h"
#include "common/mesh_import.h"
#include "common/mitsuba_bsdf.h"
#include "common/mitsuba_texture.h"
#include "common/mitsuba_xml.h"
#include "common/scene_shapes.h"
#include "common/skipped_faces.h"

namespace fs {
namespace mitsuba {
namespace {

constexpr int kDiskSegments = 64;      ///< triangles of a tessellated disk
constexpr int kSphereSubdivisions = 3; ///< icosphere levels of a tessellated sphere (1280 triangles)
constexpr int kMaxImageSide = 1 << 15; ///< as the JSON camera's resolution

/// Mitsuba's disk (the unit disk in z = 0, normal +z) as a fan of kDiskSegments triangles around its centre; the
/// polygon's radius is enlarged so that its area is the disk's, π.
void makeDisk(ShapeDesc& s) {
  const double step = 2 * kPi / kDiskSegments;
  const double r = std::sqrt(2 * kPi / (kDiskSegments * std::sin(step)));
  const uint32_t centre = uint32_t(s.vertices.size());
  s.vertices.emplace_back(0.0);
  for (int i = 0; i < kDiskSegments; ++i) s.vertices.emplace_back(r * std::cos(i * step), r * std::sin(i * step), 0.0);
  for (uint32_t i = 0; i < uint32_t(kDiskSegments); ++i) {
    Face f;
    f.v[0] = centre, f.v[1] = centre + 1 + i, f.v[2] = centre + 1 + (i + 1) % kDiskSegments;
    s.faces.push_back(f);
  }
}

/// A name for a scene element: its path, and its id if it has one.
std::string elementName(const Document& doc, pugi::xml_node node) {
  const std::string p = doc.path(node);
  return node.attribute("id") ? p + " (\"" + node.attribute("id").value() + "\")" : p;
}

/// Mitsuba's horizontal field of view, degrees, from fov + fov_axis or focal_length (its parse_fov), for a film of
/// aspect width/height.
double fovX(Plugin& p, double aspect) {
  if (p.has("fov") && p.has("focal_length")) p.doc().fail(p.node(), "give either fov or focal_length, not both");
  double fov = 0;
  std::string axis;
  if (p.has("fov")) {
    fov = p.number("fov", 0);
    axis = p.string("fov_axis", "x");
    std::transform(axis.begin(), axis.end(), axis.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (axis == "smaller") axis = aspect > 1 ? "y" : "x";
    if (axis == "larger") axis = aspect > 1 ? "x" : "y";
  } else {
    std::string f = p.string("focal_length", "50mm");
    if (f.size() > 2 && f.compare(f.size() - 2, 2, "mm") == 0) f.resize(f.size() - 2);
    char* end = nullptr;
    const double mm = std::strtod(f.c_str(), &end);
    if (f.empty() || *end != '\0' || !(mm > 0)) p.doc().fail(p.take("focal_length"), "expected a focal length like \"50mm\"");
    fov = glm::degrees(2.0 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * mm)));
    axis = "diagonal";
  }
  if (!(fov > 0 && fov < 180)) p.doc().fail(p.take("fov"), "fov must be in (0, 180) degrees");
  const double t = std::tan(glm::radians(fov) * 0.5);
  if (axis == "x") return fov;
  if (axis == "y") return glm::degrees(2.0 * std::atan(t * aspect));
  if (axis == "diagonal") return glm::degrees(2.0 * std::atan(t / std::sqrt(1.0 + 1.0 / (aspect * aspect))));
  p.doc().fail(p.take("fov_axis"), "fov_axis must be x, y, diagonal, smaller or larger");
}

class SceneReader {
 public:
  SceneReader(Document& doc, SceneDesc& scene)
      : doc_(doc), scene_(scene), textures_(doc, [this](const std::string& name) { return resolve(name); }),
        bsdfs_(doc, scene, textures_) {
    doc_.setBitmapMean([this](pugi::xml_node node) { return textures_.mean(node); });
  }

  void read() {
    for (pugi::xml_node c : doc_.scene().children()) {
      if (c.type() != pugi::node_element) continue;
      const std::string tag = c.name();
      if (tag == "default") {
        continue;  // substituted by Document
      } else if (tag == "integrator") {
        integrator(c);
      } else if (tag == "sensor") {
        if (scene_.camera.given) {
          doc_.note("sensors", "only the first sensor is used");
          doc_.ignore(c);
        } else {
          sensor(c);
        }
      } else if (tag == "shape") {
        shape(c);
      } else if (tag == "bsdf") {
        bsdfs_.material(c);
      } else if (tag == "emitter") {
        emitter(c);
      } else if (tag == "texture") {
        if (!c.attribute("id")) doc_.ignore(c);  // read where it is referenced
      } else if (tag == "path") {
        searchPaths_.push_back(resolve(c.attribute("value").value()));
      } else if (tag == "medium" || tag == "phase") {
        doc_.fail(c, "participating media are not supported");
      } else {
        doc_.fail(c, "<" + tag + "> is not supported here (default, integrator, sensor, shape, bsdf, emitter, texture, path)");
      }
    }
  }

 private:
  /// A file name relative to the scene's folder, else to a <path> folder where the file exists there.
  std::filesystem::path resolve(const std::string& name) const {
    const std::filesystem::path p(name);
    if (p.is_absolute()) return p;
    const std::filesystem::path local = std::filesystem::path(doc_.file()).parent_path() / p;
    for (const auto& dir : searchPaths_)
      if (!std::filesystem::exists(local) && std::filesystem::exists(dir / p)) return dir / p;
    return local;
  }

  void integrator(pugi::xml_node node) {
    Plugin p(doc_, node);
    const int depth = p.integer("max_depth", -1);
    if (p.type() == "direct") {
      scene_.settings.maxDepth = 1;
    } else if (depth == 0 || depth < -1) {
      doc_.fail(p.take("max_depth"), "max_depth must be -1 (unlimited) or at least 1");
    } else if (depth > 0) {
      scene_.settings.maxDepth = std::min(depth - 1, 1024);  // Mitsuba counts the camera segment, firstshot bounces
    }
    if (p.type() != "path")
      doc_.note("integrator", "integrator \"" + p.type() + "\": firstshot renders with its own integrators (max_depth read)");
    p.finish();
  }

  void sensor(pugi::xml_node node) {
    Plugin p(doc_, node);
    if (p.type() == "thinlens") {
      doc_.note("thinlens", "thinlens sensor approximated as a pinhole (no depth of field)");
      p.number("aperture_radius", 0), p.number("focus_distance", 0);
    } else if (p.type() != "perspective") {
      doc_.fail(node, "sensor type \"" + p.type() + "\" is not supported (perspective; thinlens as a pinhole)");
    }
    CameraDesc& c = scene_.camera;
    c.width = 768, c.height = 576;  // Mitsuba's hdrfilm defaults
    for (pugi::xml_node film : p.nested("film")) {
      Plugin f(doc_, film);
      c.width = f.integer("width", c.width), c.height = f.integer("height", c.height);
      if (c.width < 1 || c.height < 1 || c.width > kMaxImageSide || c.height > kMaxImageSide)
        doc_.fail(film, "width and height must be in [1, " + std::to_string(kMaxImageSide) + "]");
      f.finish();
    }
    for (pugi::xml_node sampler : p.nested("sampler")) {
      Plugin s(doc_, sampler);
      scene_.settings.spp = s.integer("sample_count", 4);  // Mitsuba's default
      if (scene_.settings.spp < 1) doc_.fail(s.take("sample_count"), "sample_count must be at least 1");
      s.finish();
    }
    const double aspect = double(c.width) / c.height;
    c.fovYDeg = glm::degrees(2.0 * std::atan(std::tan(glm::radians(fovX(p, aspect)) * 0.5) / aspect));
    const Mat4d m = p.transform("to_world");
    c.position = Vec3d(m * glm::dvec4(0, 0, 0, 1));
    const Vec3d forward = Vec3d(m * glm::dvec4(0, 0, 1, 0)), up = Vec3d(m * glm::dvec4(0, 1, 0, 0));
    if (!(glm::length(forward) > 0 && glm::length(glm::cross(forward, up)) > 0))
      doc_.fail(node, "to_world maps the view direction or up to zero, or makes them parallel");
    c.lookAt = c.position + glm::normalize(forward);
    c.up = glm::normalize(up);
    if (glm::determinant(glm::dmat3(m)) < 0)
      doc_.note("mirrored camera", "the sensor's to_world mirrors the image; rendered without the mirroring");
    c.given = true;
    p.finish();
  }

  void shape(pugi::xml_node node) {
    Plugin p(doc_, node);
    ShapeDesc s;
    s.name = elementName(doc_, node);
    const std::string& t = p.type();
    if (t == "obj" || t == "ply") {
      s.type = ShapeType::Mesh;
      const std::string name = p.string("filename", "");
      if (name.empty()) doc_.fail(node, "missing <string name=\"filename\">");
      s.sourceFile = resolve(name).string();
      MeshData mesh = loadMeshFile(s.sourceFile, doc_.file(), doc_.where(node));
      s.vertices = std::move(mesh.vertices);
      s.faces = std::move(mesh.faces);
      s.uv = std::move(mesh.uv);
      s.normals = std::move(mesh.normals);  // issue 34
      s.tangents = std::move(mesh.tangents), s.bitangents = std::move(mesh.bitangents);
    } else if (t == "rectangle") {
      s.type = ShapeType::Quad;
      shapes::makeQuad(s, {Vec3d(-1, -1, 0), Vec3d(1, -1, 0), Vec3d(1, 1, 0), Vec3d(-1, 1, 0)});
      for (Vec2& uv : s.uv) uv.y = 1.0f - uv.y;  // Mitsuba's: (u, v) = ((x + 1)/2, (y + 1)/2)
    } else if (t == "cube") {
      s.type = ShapeType::Box;
      shapes::makeBox(s, Vec3d(-1.0), Vec3d(1.0));
    } else if (t == "sphere") {
      s.type = ShapeType::Sphere;
      const double radius = p.number("radius", 1.0);
      if (!(radius > 0)) doc_.fail(p.take("radius"), "radius must be positive");
      shapes::makeSphere(s, p.point("center", Vec3d(0.0)), radius, kSphereSubdivisions);
    } else if (t == "disk") {
      s.type = ShapeType::Mesh;
      makeDisk(s);
    } else {
      doc_.fail(node, "shape type \"" + t + "\" is not supported (obj, ply, rectangle, cube, sphere, disk)");
    }
    shapes::transform(s, p.transform("to_world"));
    if (p.boolean("flip_normals", false)) shapes::flip(s);
    std::vector<pugi::xml_node> bsdfs = p.nested("bsdf");
    if (const pugi::xml_node named = p.take("bsdf")) bsdfs.push_back(doc_.resolve(named));
    if (bsdfs.size() > 1) doc_.fail(node, "a shape takes one bsdf");
    s.material = bsdfs.empty() ? bsdfs_.defaultMaterial() : bsdfs_.material(bsdfs[0]);
    for (pugi::xml_node e : p.nested("emitter")) {
      Plugin emitter(doc_, e);
      if (emitter.type() != "area") doc_.fail(e, "emitter type \"" + emitter.type() + "\" inside a shape (only area)");
      MaterialDesc m = scene_.materials[s.material];
      m.name = s.name + " emitter";
      if (m.isCutout()) {  // an emitter cannot be a cut-out here
        doc_.note("masked emitter", "a masked area emitter is opaque (its mask's opacity is dropped)");
        m.alphaMode = AlphaMode::Opaque, m.alphaTexture = nullptr, m.alpha = 1.0f;
      }
      m.emission = emitter.color("radiance", Color(1.0f));
      emitter.finish();
      scene_.materials.push_back(m);
      s.material = int(scene_.materials.size() - 1);
    }
    p.finish();
    scene_.shapes.push_back(std::move(s));
  }

  void emitter(pugi::xml_node node) {
    Plugin p(doc_, node);
    LightDesc l;
    l.name = elementName(doc_, node);
    const Mat4d m = p.transform("to_world");
    const Vec3d origin(m * glm::dvec4(0, 0, 0, 1)), axis(m * glm::dvec4(0, 0, 1, 0));
    const std::string& t = p.type();
    if (t == "point") {
      l.type = LightType::Point;
      l.position = p.point("position", origin);
      l.power = p.color("intensity", Color(1.0f)) * float(4 * kPi);  // W/sr → W
    } else if (t == "spot") {
      l.type = LightType::Spot;
      l.position = origin;
      l.direction = axis;
      l.outerAngleDeg = p.number("cutoff_angle", 20.0);
      l.innerAngleDeg = std::min(p.number("beam_width", 0.75 * l.outerAngleDeg), l.outerAngleDeg);
      if (!(l.outerAngleDeg > 0 && l.outerAngleDeg <= 180 && l.innerAngleDeg > 0))
        doc_.fail(node, "cutoff_angle and beam_width must be in (0, 180] degrees");
      l.power = p.color("intensity", Color(1.0f)) * float(SpotCone(l).integral());  // on-axis W/sr → W
      doc_.note("spot", "spot falloff: Mitsuba's linear ramp in angle from beam_width to cutoff_angle approximated by "
                        "a smoothstep in cos(angle) over the same cone (same on-axis intensity)");
    } else if (t == "directional") {
      l.type = LightType::Directional;
      l.direction = p.point("direction", axis);
      l.irradiance = p.color("irradiance", Color(1.0f));
    } else if (t == "area") {
      doc_.fail(node, "an area emitter belongs inside a <shape>");
    } else {
      doc_.fail(node, "emitter type \"" + t + "\" is not supported (point, spot, directional; area inside a shape; "
                      "environment emitters are refused)");
    }
    p.finish();
    scene_.lights.push_back(l);
  }

  Document& doc_;
  SceneDesc& scene_;
  TextureMapper textures_;
  BsdfMapper bsdfs_;
  std::vector<std::filesystem::path> searchPaths_;
};

}  // namespace
}  // namespace mitsuba

SceneDesc parseSceneMitsuba(const std::string& text, const std::string& path) {
  mitsuba::Document doc(path, text);
  SceneDesc scene;
  scene.file = path;
  mitsuba::SceneReader(doc, scene).read();
  skipDegenerateFaces(scene);  // the faces are final: zero-area and duplicate ones skipped, with a line on stderr
  doc.flush();
  return scene;
}

SceneDesc loadSceneMitsuba(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseSceneMitsuba(ss.str(), path);
}

}  // namespace fs
