// SceneDesc: validation, bounds and the content hash.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/lights/ies.h"
#include "common/materials/texture.h"
#include "common/materials/thin_glass.h"
#include "common/patches/patch_cutouts.h"
#include "common/scene/scene_desc.h"
#include "common/scene/scene_shapes.h"
#include "common/scene/skipped_faces.h"
#include "common/scene/sky_desc.h"
#include "common/util/error.h"
#include "common/util/hash.h"

namespace firstshot {

int SceneDesc::findMaterial(const std::string& name) const {
  for (size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == name) return static_cast<int>(i);
  return -1;
}

void SceneDesc::bounds(Vec3d& lo, Vec3d& hi) const {
  lo = Vec3d(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const auto& s : shapes)
    for (const auto& p : s.vertices) lo = glm::min(lo, p), hi = glm::max(hi, p);
  for (const auto& l : lights)
    if (l.type == LightType::Point || l.type == LightType::Spot) lo = glm::min(lo, l.position), hi = glm::max(hi, l.position);
  if (lo.x > hi.x) lo = hi = Vec3d(0.0);
}

namespace {

void validateShape(const SceneDesc& scene, const ShapeDesc& s) {
  for (size_t i = 0; i < s.vertices.size(); ++i)
    if (!isFinite(s.vertices[i]))
      throw InputError(scene.file, s.name, "vertex " + std::to_string(i) + (s.sourceFile.empty() ? "" : " of " + s.sourceFile) +
                                               " is not finite (NaN or Inf)");
  if (scene.materials[s.material].isEmissive()) {
    double area = 0;
    for (const Face& f : s.faces)
      if (f.count >= 3 && f.count <= 4 && f.v[0] < s.vertices.size() && f.v[1] < s.vertices.size() &&
          f.v[2] < s.vertices.size() && (f.count == 3 || f.v[3] < s.vertices.size()))
        area += shapes::faceArea(s, f);
    if (!(area > 0)) throw InputError(scene.file, s.name, "emitter has zero area");
  }
  const bool fromFile = !s.sourceFile.empty();
  for (size_t k = 0; k < s.faces.size(); ++k) {
    const Face& f = s.faces[k];
    const std::string what = fromFile ? "triangle " + std::to_string(k) + " of " + s.sourceFile : "face " + std::to_string(k);
    if (f.count != 3 && f.count != 4) throw InputError(scene.file, s.name, what + " has " + std::to_string(f.count) + " vertices");
    for (int i = 0; i < f.count; ++i)
      if (f.v[i] >= s.vertices.size()) throw InputError(scene.file, s.name, what + " has a vertex index out of range");
    // The loaders skip zero-area faces (skipDegenerateFaces); a scene built otherwise may still hold one.
    if (hasZeroArea(s, f)) throw InputError(scene.file, s.name, what + " is degenerate (zero area)");
  }
}

/// A thin glass pane's keys (common/materials/thin_glass.h): ior ≥ 1, transmittance in [0, 1] and at most a lossless
/// pane's. @p w names the material ("materials.NAME").
void validateThinGlass(const std::string& file, const std::string& w, const MaterialDesc& m) {
  if (!isFinite(m.transmittance) || !std::isfinite(m.ior)) throw InputError(file, w, "a value is not finite (NaN or Inf)");
  if (!(m.ior >= 1.0f)) throw InputError(file, w + ".ior", "a glass pane's index must be at least 1 (got " + std::to_string(m.ior) + ")");
  const float lo = std::min(m.transmittance.x, std::min(m.transmittance.y, m.transmittance.z)), hi = maxComponent(m.transmittance);
  if (lo < 0.0f || hi > 1.0f)
    throw InputError(file, w + ".transmittance", "material \"" + m.name + "\": must be in [0, 1] (got " + std::to_string(lo < 0.0f ? lo : hi) + ")");
  const float most = ThinGlassBSDF::maxTransmittance(m.ior);
  if (hi > most * (1.0f + 1e-6f))
    throw InputError(file, w + ".transmittance", "material \"" + m.name + "\": " + std::to_string(hi) + " exceeds " + std::to_string(most) +
                                                     ", what a lossless pane of ior " + std::to_string(m.ior) +
                                                     " transmits (its two faces reflect the rest)");
}

/// A conductor's Fresnel (mirror and pbr only): η and k finite and ≥ 0. @p w names the material.
void validateConductor(const std::string& file, const std::string& w, const MaterialDesc& m) {
  if (m.type != MaterialType::Mirror && m.type != MaterialType::Pbr)
    throw InputError(file, w, "material \"" + m.name + "\": a conductor's eta and k apply to mirror and pbr materials");
  const ConductorFresnel& c = *m.conductor;
  if (!isFinite(c.eta()) || !isFinite(c.k())) throw InputError(file, w, "a value is not finite (NaN or Inf)");
  if (glm::any(glm::lessThan(c.eta(), Color(0.0f))) || glm::any(glm::lessThan(c.k(), Color(0.0f))))
    throw InputError(file, w, "material \"" + m.name + "\": a conductor's eta and k must not be negative");
}

void frameCamera(SceneDesc& scene) {
  Vec3d lo, hi;
  scene.bounds(lo, hi);
  CameraDesc& c = scene.camera;
  const Vec3d centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * glm::length(hi - lo), 1e-3);
  const double halfFov = glm::radians(c.fovYDeg) * 0.5;
  c.lookAt = centre;
  c.up = Vec3d(0, 1, 0);
  c.position = centre + Vec3d(0, 0, radius / std::sin(halfFov) * 1.05);
}

}  // namespace

void validateScene(SceneDesc& scene) {
  const std::string& file = scene.file;
  const SettingsDesc& st = scene.settings;
  if (!(st.patchSize >= 0)) throw InputError(file, "settings.patch_size", "must be positive");
  if (!(st.lightPatchSize >= 0)) throw InputError(file, "settings.light_patch_size", "must be positive");
  if (!(st.minPatchSize >= 0)) throw InputError(file, "settings.min_patch_size", "must be positive");
  if (st.patchSize > 0 && st.minPatchSize > st.patchSize) throw InputError(file, "settings.min_patch_size", "must not exceed settings.patch_size");
  if (scene.materials.empty()) throw InputError(file, "materials", "the scene defines no material");
  for (const auto& m : scene.materials) {
    const std::string w = "materials." + m.name;
    if (!isFinite(m.albedo) || !isFinite(m.specular) || !isFinite(m.emission))
      throw InputError(file, w, "a value is not finite (NaN or Inf)");
    if (glm::any(glm::lessThan(m.albedo, Color(0.0f))) || glm::any(glm::lessThan(m.emission, Color(0.0f))) ||
        glm::any(glm::lessThan(m.specular, Color(0.0f))))
      throw InputError(file, w, "negative albedo, specular or emission");
    if (maxComponent(m.albedo) > 1.0f) throw InputError(file, w + ".albedo", "albedo above 1 reflects more light than it receives");
    if (m.type == MaterialType::Glossy && maxComponent(m.albedo + m.specular) > 1.0f)
      throw InputError(file, w, "albedo + specular above 1 reflects more light than it receives");
    if (m.type == MaterialType::Mirror && maxComponent(m.specular) > 1.0f)
      throw InputError(file, w + ".specular", "mirror reflectance above 1");
    if ((m.type == MaterialType::Dielectric || m.type == MaterialType::Pbr) && !(m.ior > 0))
      throw InputError(file, w + ".ior", "must be positive");
    if (m.type == MaterialType::ThinGlass) validateThinGlass(file, w, m);
    validateCutout(file, w, m);  // alpha (cut-outs)
    if (m.type == MaterialType::Pbr && !(m.metallic >= 0.0f && m.metallic <= 1.0f))
      throw InputError(file, w + ".metallic", "must be in [0, 1]");
    if (m.type == MaterialType::Pbr && !(m.roughness >= 0.0f && m.roughness <= 1.0f))
      throw InputError(file, w + ".roughness", "must be in [0, 1]");
    if (m.conductor) validateConductor(file, w, m);
  }
  if (scene.shapes.empty()) throw InputError(file, "shapes", "the scene has no shapes");
  for (const auto& s : scene.shapes) {
    if (s.material < 0 || size_t(s.material) >= scene.materials.size())
      throw InputError(file, s.name, "material index out of range");
    validateShape(scene, s);
  }
  // Point, spot and directional lights.
  for (auto& l : scene.lights) {
    if (l.type == LightType::Area) continue;
    if (!isFinite(l.position) || !isFinite(l.direction) || !isFinite(l.power) || !isFinite(l.irradiance))
      throw InputError(file, l.name, "a value is not finite (NaN or Inf)");
    if (glm::any(glm::lessThan(l.power, Color(0.0f))) || glm::any(glm::lessThan(l.irradiance, Color(0.0f))))
      throw InputError(file, l.name, "negative power or irradiance");
    if (l.type != LightType::Point) {
      if (!(glm::length(l.direction) > 0)) throw InputError(file, l.name + ".direction", "direction is zero");
      l.direction = glm::normalize(l.direction);
    }
    if (l.ies && glm::length(glm::cross(glm::normalize(l.iesReference), l.direction)) < 1e-6 &&
        glm::length(l.iesReference) > 0)
      throw InputError(file, l.name + ".ies_reference", "the reference vector is parallel to the direction");
    if (l.type == LightType::Spot && !l.ies && !(l.innerAngleDeg <= l.outerAngleDeg && l.outerAngleDeg <= 180))
      throw InputError(file, l.name, "spot angles need 0 < inner_angle <= outer_angle <= 180");
  }
  // Area lights: one per emissive shape (added once).
  const bool haveArea = std::any_of(scene.lights.begin(), scene.lights.end(),
                                    [](const LightDesc& l) { return l.type == LightType::Area; });
  if (!haveArea) {
    for (size_t i = 0; i < scene.shapes.size(); ++i) {
      const ShapeDesc& s = scene.shapes[i];
      const MaterialDesc& m = scene.materials[s.material];
      if (!m.isEmissive()) continue;
      LightDesc l;
      l.name = s.name;
      l.type = LightType::Area;
      l.shape = static_cast<int>(i);
      l.small = s.small;
      l.luminaire = s.luminaire;  // an emitter of a luminaire is one of its lights
      scene.lights.push_back(l);
    }
  }
  if (scene.lights.empty() && !scene.sky && !scene.environment)  // e.g. a glTF asset made for a viewer's lighting
    std::fprintf(stderr, "%s: no lights, no emissive surfaces, no sky: the images are black\n", file.c_str());
  // Camera.
  CameraDesc& c = scene.camera;
  if (!(c.fovYDeg > 0 && c.fovYDeg < 180)) throw InputError(file, "camera.fov_y", "must be in (0, 180) degrees");
  if (!c.given) frameCamera(scene);
  if (!(glm::length(c.lookAt - c.position) > 0)) throw InputError(file, "camera", "position and look_at coincide");
  if (!(glm::length(glm::cross(c.lookAt - c.position, c.up)) > 0))
    throw InputError(file, "camera.up", "up is zero or parallel to the viewing direction");
}

namespace {

/// A cut-out material's alpha: nothing for an opaque one, so that scenes without cut-outs keep their hashes.
void hashAlpha(Hasher& h, const MaterialDesc& m) {
  if (!m.isCutout()) return;
  h.add(std::string_view("alpha")).add(m.alphaMode).add(m.alphaCutoff).add(m.alpha);
  if (!m.alphaTexture) return;
  const TexelImage& im = *m.alphaTexture->image;
  h.add(m.alphaTexture->hash()).bytes(im.alpha.data(), im.alpha.size() * sizeof(float));
}

}  // namespace

uint64_t hashScene(const SceneDesc& scene) {
  // Everything that changes light transport: geometry, materials, lights. Not the camera or the
  // render settings, so a first-shot table stays valid when only the view changes.
  Hasher h;
  h.add(std::string_view("firstshot-scene-v1"));
  h.add<uint64_t>(scene.materials.size());
  for (const auto& m : scene.materials) {
    h.add(m.type).add(m.albedo).add(m.specular).add(m.exponent).add(m.ior).add(m.transmittance).add(m.emission);
    if (m.type == MaterialType::Pbr) h.add(m.metallic).add(m.roughness);  // other types keep their hashes
    if (m.albedoTexture) h.add(m.albedoTexture->hash());  // untextured scenes hash as before
    if (m.metallicRoughnessTexture) h.add(uint8_t(2)).add(m.metallicRoughnessTexture->hash());
    hashAlpha(h, m);
    if (m.normalTexture) h.add(uint8_t(3)).add(m.normalTexture->hash()).add(m.normalScale);
    if (m.emissionTexture) h.add(uint8_t(6)).add(m.emissionTexture->hash()).add(m.emissionFactor);
    if (m.conductor) h.add(uint8_t(10)).add(m.conductor->eta()).add(m.conductor->k());  // others hash as before
    if (m.microfacet != MicrofacetModel::Ggx) h.add(uint8_t(11)).add(m.microfacet);
  }
  h.add<uint64_t>(scene.shapes.size());
  for (const auto& s : scene.shapes) {
    h.add(s.material).add(s.small).add<uint64_t>(s.vertices.size()).add<uint64_t>(s.faces.size());
    if (!s.vertices.empty()) h.bytes(s.vertices.data(), s.vertices.size() * sizeof(Vec3d));
    for (const auto& f : s.faces) h.add(f.count).bytes(f.v, sizeof(f.v[0]) * f.count);
    const bool textured = s.material >= 0 && size_t(s.material) < scene.materials.size() &&
                          scene.materials[size_t(s.material)].hasTextures();
    if (textured && s.hasUv()) h.bytes(s.uv.data(), s.uv.size() * sizeof(Vec2));  // only where they change results
    const bool cutByTexture = !textured && s.material >= 0 && size_t(s.material) < scene.materials.size() &&
                              scene.materials[size_t(s.material)].isCutout() && scene.materials[size_t(s.material)].alphaTexture;
    if (cutByTexture && s.hasUv()) h.bytes(s.uv.data(), s.uv.size() * sizeof(Vec2));
    // Shading normals, and the coordinates a normal map alone reads (untextured, unmapped shapes as before).
    const bool mapped = s.material >= 0 && size_t(s.material) < scene.materials.size() &&
                        scene.materials[size_t(s.material)].normalTexture;
    if (mapped && !textured && s.hasUv()) h.bytes(s.uv.data(), s.uv.size() * sizeof(Vec2));
    const bool glowing = s.material >= 0 && size_t(s.material) < scene.materials.size() &&
                         scene.materials[size_t(s.material)].emissionTexture;  // emission per point
    if (glowing && s.hasUv()) h.add(uint8_t(7)).bytes(s.uv.data(), s.uv.size() * sizeof(Vec2));
    if (s.hasNormals()) h.add(uint8_t(4)).bytes(s.normals.data(), s.normals.size() * sizeof(Vec3));
    if (!s.luminaire.empty()) h.add(uint8_t(8)).add(std::string_view(s.luminaire));  // unnamed shapes as before
    if (mapped && s.hasTangents())  // glTF TANGENT: only what a normal map reads (other shapes hash as before)
      h.add(uint8_t(5)).bytes(s.tangents.data(), s.tangents.size() * sizeof(Vec3))
          .bytes(s.bitangents.data(), s.bitangents.size() * sizeof(Vec3));
  }
  h.add<uint64_t>(scene.lights.size());
  for (const auto& l : scene.lights) {
    h.add(l.type).add(l.position).add(l.direction).add(l.power).add(l.irradiance);
    h.add(l.innerAngleDeg).add(l.outerAngleDeg).add(l.shape).add(l.small);
    if (!l.luminaire.empty()) h.add(uint8_t(9)).add(std::string_view(l.luminaire));  // unnamed lights as before
    if (l.ies) {  // the table itself (not its file name)
      h.add(int(l.ies->type)).add(l.iesReference).add<uint64_t>(l.ies->candela.size());
      h.bytes(l.ies->vertical.data(), l.ies->vertical.size() * sizeof(double));
      h.bytes(l.ies->horizontal.data(), l.ies->horizontal.size() * sizeof(double));
      h.bytes(l.ies->candela.data(), l.ies->candela.size() * sizeof(double));
    }
  }
  // Daylight: only when present, so that scenes without it keep their hashes. The table does not hold the
  // sky (a large light), but a table belongs to one scene: the renderer's check then also catches a changed sky.
  if (scene.sky) {
    const SkyDesc& s = *scene.sky;
    h.add(std::string_view("sky")).add(s.dome.type()).add(s.dome.sunDirection()).add(s.dome.zenithLuminance());
    h.add(s.dome.horizontalIlluminance()).add(s.perez.diffuseHorizontal).add(s.perez.directNormal);
    h.add(s.perez.dayOfYear).add(s.groundReflectance).add(s.sunHorizontalLux);
    if (s.turbidity > 0) h.add(std::string_view("turbidity")).add(s.turbidity);
  }
  if (scene.environment) {
    const EnvironmentDesc& e = *scene.environment;
    std::ifstream in(e.file, std::ios::binary);  // the image's bytes, not its name: a moved scene keeps its hash
    std::stringstream bytes;
    bytes << in.rdbuf();
    h.add(std::string_view("environment")).add(std::string_view(bytes.str())).add(e.scale).add(e.rotateDeg);
    if (e.file.empty()) h.add(std::string_view("constant")).add(e.constant);
  }
  return h.value();
}

}  // namespace firstshot
