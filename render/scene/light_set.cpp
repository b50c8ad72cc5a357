// Light sampling for next-event estimation.
#include "render/scene/light_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/materials/emission_texture.h"
#include "common/sampling/sampling.h"
#include "common/scene/sky_desc.h"
#include "render/scene/sky_light.h"

namespace firstshot {

namespace {

/// The emitting triangles of an emissive shape (quads split along v0–v2), vertices in float.
EmitterMesh triangulate(const ShapeDesc& s) {
  EmitterMesh m;
  m.vertices.reserve(s.vertices.size());
  for (const Vec3d& v : s.vertices) m.vertices.emplace_back(v);
  for (const Face& f : s.faces) {
    m.indices.insert(m.indices.end(), {f.v[0], f.v[1], f.v[2]});
    if (f.count == 4) m.indices.insert(m.indices.end(), {f.v[0], f.v[2], f.v[3]});
  }
  return m;
}

/// What @p l needs to emit per point when its shape @p s of material @p mat has an emission texture
/// (common/materials/emission_texture.h): the corners' texture coordinates per triangle, as triangulate() cuts the faces,
/// and each triangle's mean radiance.
void addEmissionTexture(RenderLight& l, const MaterialDesc& mat, const ShapeDesc& s) {
  if (!emitsPerPoint(mat, s)) return;
  l.textured = std::make_shared<const MaterialDesc>(mat);
  for (size_t f = 0; f < s.faces.size(); ++f)
    for (int k = 1; k + 1 < s.faces[f].count; ++k) {
      const Vec2 uv[3] = {s.cornerUv(f, 0), s.cornerUv(f, k), s.cornerUv(f, k + 1)};
      l.triangleUv.insert(l.triangleUv.end(), uv, uv + 3);
      l.triangleRadiance.push_back(meanEmissionOverTriangle(mat, uv[0], uv[1], uv[2]));
    }
}

/// Barycentric coordinates (β, γ) of @p p in triangle (@p a, @p b, @p c), projected onto its plane; 0 if degenerate.
Vec2 emitterHitBarycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  const Vec3 e1 = b - a, e2 = c - a, d = p - a;
  const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const float p1 = glm::dot(d, e1), p2 = glm::dot(d, e2), det = d11 * d22 - d12 * d12;
  if (!(det > 0.0f)) return Vec2(0.0f);
  return glm::clamp(Vec2(d22 * p1 - d12 * p2, d11 * p2 - d12 * p1) / det, Vec2(0.0f), Vec2(1.0f));
}

}  // namespace

LightSet::LightSet(const SceneDesc& scene, const std::vector<uint32_t>& replaced) {
  for (uint32_t i = 0; i < scene.lights.size(); ++i) {
    const LightDesc& d = scene.lights[i];
    RenderLight l;
    l.type = d.type;
    l.sceneIndex = i;
    l.replaced = std::find(replaced.begin(), replaced.end(), i) != replaced.end();
    l.desc = d;
    l.position = Vec3(d.position);
    l.direction = Vec3(d.direction);
    switch (d.type) {
      case LightType::Point:
      case LightType::Spot:
        l.profile = EmissionProfile(d);
        l.intensity = l.profile.peakIntensity(d);
        break;
      case LightType::Directional: l.irradiance = d.irradiance; break;
      case LightType::Area: {
        const ShapeDesc& shape = scene.shapes[size_t(d.shape)];
        l.emitter = static_cast<uint32_t>(meshes_.size());
        l.radiance = scene.materials[size_t(shape.material)].emission;
        addEmissionTexture(l, scene.materials[size_t(shape.material)], shape);
        meshes_.push_back(triangulate(shape));
        emitterLight_.push_back(static_cast<uint32_t>(lights_.size()));
        const EmitterMesh& m = meshes_.back();
        std::vector<double> areas(m.triangleCount());
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
          const Vec3d a(m.vertices[m.indices[3 * t]]), b(m.vertices[m.indices[3 * t + 1]]), c(m.vertices[m.indices[3 * t + 2]]);
          areas[t] = 0.5 * glm::length(glm::cross(b - a, c - a));
        }
        l.triangles = Distribution1Df(areas);
        l.area = l.triangles.total();
        break;
      }
    }
    lights_.push_back(std::move(l));
  }
  environment_ = makeInfiniteLight(scene);
  sky_ = scene.sky;
}

Color LightSet::background(const Vec3& dir) const {
  if (sky_) return Color(skyRadiance(dir.y > 0.0f ? sky_->dome.luminance(Vec3d(dir)) : sky_->groundLuminance()));
  return environment_ ? environment_->radiance(dir) : Color(0.0f);
}

size_t LightSet::unreplacedCount() const {
  return static_cast<size_t>(std::count_if(lights_.begin(), lights_.end(), [](const RenderLight& l) { return !l.replaced; }));
}

bool LightSet::sample(const RenderLight& l, const Vec3& x, const Vec2& u, LightRecord& out) const {
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot: {
      const Vec3 d = l.position - x;
      const float dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0f)) return false;
      out.distance = std::sqrt(dist2);
      out.wi = d / out.distance;
      out.pdf = 0.0f;
      Color intensity = l.intensity;
      if (l.type == LightType::Spot) intensity *= l.profile(-out.wi);
      out.value = intensity / dist2;
      return maxComponent(out.value) > 0.0f;
    }
    case LightType::Directional:
      out.wi = -l.direction;
      out.distance = std::numeric_limits<float>::infinity();
      out.pdf = 0.0f;
      out.value = l.irradiance;
      return maxComponent(out.value) > 0.0f;
    case LightType::Area: {
      Vec3 y, n;
      Color le;
      if (!samplePoint(l, u, y, n, &le)) return false;
      const Vec3 d = y - x;
      const float dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0f)) return false;
      out.distance = std::sqrt(dist2);
      out.wi = d / out.distance;
      const float cosL = -glm::dot(n, out.wi);
      if (!(cosL > 0.0f)) return false;  // one-sided: x is behind this triangle
      out.pdf = static_cast<float>(dist2 / (cosL * l.area));
      out.value = le / out.pdf;
      return std::isfinite(out.pdf) && maxComponent(out.value) > 0.0f;
    }
  }
  return false;
}

bool LightSet::samplePoint(const RenderLight& l, const Vec2& u, Vec3& y, Vec3& n, Color* le) const {
  if (l.type != LightType::Area || l.triangles.empty() || !(l.area > 0)) return false;
  // Choose a triangle by area, then reuse the remainder of u.x inside it.
  float ux = 0;
  const size_t t = l.triangles.sampleDiscrete(u.x, &ux);
  const EmitterMesh& m = meshes_[l.emitter];
  const Vec3 a = m.vertices[m.indices[3 * t]], b = m.vertices[m.indices[3 * t + 1]], c = m.vertices[m.indices[3 * t + 2]];
  const Vec3 bary = squareToUniformTriangle(Vec2(ux, u.y));
  y = bary.x * a + bary.y * b + bary.z * c;
  n = glm::normalize(glm::cross(b - a, c - a));
  if (le) *le = radianceAt(l, uint32_t(t), Vec2(bary.y, bary.z));
  return true;
}

Color LightSet::emitted(const Hit& hit, const Vec3& wo) const {
  if (!(glm::dot(hit.ng, wo) > 0.0f)) return Color(0.0f);
  const RenderLight& l = emitterLight(hit.emitter);
  if (!l.textured) return l.radiance;
  const EmitterMesh& m = meshes_[hit.emitter];
  const uint32_t* v = &m.indices[3 * size_t(hit.triangle)];
  const Vec2 bary = emitterHitBarycentric(m.vertices[v[0]], m.vertices[v[1]], m.vertices[v[2]], hit.p);
  return radianceAt(l, hit.triangle, bary);
}

Color LightSet::radianceAt(const RenderLight& l, uint32_t t, const Vec2& bary) const {
  if (!l.textured) return l.radiance;
  const Vec2* uv = &l.triangleUv[3 * size_t(t)];
  return emissionAt(*l.textured, uv[0] + bary.x * (uv[1] - uv[0]) + bary.y * (uv[2] - uv[0]));
}

float LightSet::pdf(const RenderLight& l, const Vec3& x, const Vec3& y, const Vec3& ng) const {
  if (l.type != LightType::Area || !(l.area > 0)) return 0.0f;
  const Vec3 d = y - x;
  const float dist2 = glm::dot(d, d);
  const float cosL = -glm::dot(ng, d) / std::sqrt(dist2);
  if (!(cosL > 0.0f)) return 0.0f;
  return static_cast<float>(dist2 / (cosL * l.area));
}

}  // namespace firstshot
