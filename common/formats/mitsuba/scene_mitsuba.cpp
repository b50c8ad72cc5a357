// Mitsuba 3 XML scenes → SceneDesc: the scene's elements, emitters and the sensor (docs/scene-format.md, "Mitsuba 3
// XML scenes"); shapes in mitsuba_shapes.cpp, bsdfs in mitsuba_bsdf.cpp, XML in mitsuba_xml.cpp.
#include "common/formats/mitsuba/scene_mitsuba.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common/formats/mitsuba/mitsuba_bsdf.h"
#include "common/formats/mitsuba/mitsuba_emitters.h"
#include "common/formats/mitsuba/mitsuba_shapes.h"
#include "common/formats/mitsuba/mitsuba_texture.h"
#include "common/formats/mitsuba/mitsuba_xml.h"
#include "common/lights/spot_cone.h"
#include "common/scene/camera_fov.h"
#include "common/scene/skipped_faces.h"
#include "common/util/error.h"

namespace firstshot {
namespace mitsuba {
namespace {

constexpr int kMaxImageSide = 1 << 15; ///< as the JSON camera's resolution

/// A sensor's field of view as Mitsuba's parse_fov reads it: `fov` (degrees) on `fov_axis`, or `focal_length` on the
/// diagonal of 36 × 24 mm film.
struct SensorFov {
  double deg = 0;
  FovAxis axis = FovAxis::X;
};

SensorFov sensorFov(Plugin& p) {
  if (p.has("fov") && p.has("focal_length")) p.doc().fail(p.node(), "give either fov or focal_length, not both");
  SensorFov f;
  if (p.has("fov")) {
    f.deg = p.number("fov", 0);
    std::string axis = p.string("fov_axis", "x");
    std::transform(axis.begin(), axis.end(), axis.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    const std::map<std::string, FovAxis> axes = {{"x", FovAxis::X}, {"y", FovAxis::Y}, {"diagonal", FovAxis::Diagonal},
                                                 {"smaller", FovAxis::Smaller}, {"larger", FovAxis::Larger}};
    if (!axes.count(axis)) p.doc().fail(p.take("fov_axis"), "fov_axis must be x, y, diagonal, smaller or larger");
    f.axis = axes.at(axis);
  } else {
    std::string text = p.string("focal_length", "50mm");
    if (text.size() > 2 && text.compare(text.size() - 2, 2, "mm") == 0) text.resize(text.size() - 2);
    char* end = nullptr;
    const double mm = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(mm > 0)) p.doc().fail(p.take("focal_length"), "expected a focal length like \"50mm\"");
    f.deg = glm::degrees(2.0 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * mm)));
    f.axis = FovAxis::Diagonal;
  }
  if (!(f.deg > 0 && f.deg < 180)) p.doc().fail(p.take("fov"), "fov must be in (0, 180) degrees");
  return f;
}

class SceneReader {
 public:
  SceneReader(Document& doc, SceneDesc& scene)
      : doc_(doc), scene_(scene), textures_(doc, [this](const std::string& name) { return resolve(name); }),
        bsdfs_(doc, scene, textures_),
        shapes_(doc, scene, bsdfs_, [this](const std::string& name) { return resolve(name); }) {
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
        shapes_.add(c);
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
      const double aperture = p.number("aperture_radius", 0), focus = p.number("focus_distance", 1);
      if (!(aperture >= 0)) doc_.fail(p.take("aperture_radius"), "aperture_radius must not be negative");
      if (!(focus > 0)) doc_.fail(p.take("focus_distance"), "focus_distance must be positive");
      doc_.note("thinlens", "thinlens sensor rendered as a pinhole at its position: no depth of field, everything in "
                            "focus (aperture_radius and focus_distance read, not used)");
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
    const SensorFov fov = sensorFov(p);
    c.fovAxis = fov.axis;  // kept when firstshot-render changes the resolution (common/scene/camera_fov.h)
    c.fovYDeg = verticalFov(fov.axis, fov.deg, double(c.width) / c.height);
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

  void emitter(pugi::xml_node node) {
    readEmitter(doc_, node, scene_, [this](const std::string& name) { return resolve(name); });
  }

  Document& doc_;
  SceneDesc& scene_;
  TextureMapper textures_;
  BsdfMapper bsdfs_;
  ShapeMapper shapes_;
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

}  // namespace firstshot
