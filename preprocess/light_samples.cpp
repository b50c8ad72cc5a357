#include "preprocess/light_samples.h"

#include <array>
#include <map>

#include "common/patches.h"

namespace fs {

namespace {

/// Vertex samples of one emissive shape: shared vertices merged exactly (same double coordinates).
void areaSamples(const SceneDesc& scene, uint32_t lightIndex, double lightPatchSize, std::vector<LightSample>& out) {
  const LightDesc& light = scene.lights[lightIndex];
  const ShapeDesc& shape = scene.shapes[light.shape];
  const Color le = scene.materials[shape.material].emission;
  struct Acc {
    double area = 0;
    Vec3d normal{0.0};
  };
  std::map<std::array<double, 3>, size_t> index;
  std::vector<Vec3d> positions;
  std::vector<Acc> acc;
  auto vertex = [&](const Vec3d& p) {
    const std::array<double, 3> key{p.x, p.y, p.z};
    auto [it, inserted] = index.emplace(key, positions.size());
    if (inserted) {
      positions.push_back(p);
      acc.emplace_back();
    }
    return it->second;
  };
  std::vector<std::vector<Vec3d>> polys;
  for (const Face& f : shape.faces) {
    Vec3d v[4];
    for (int i = 0; i < f.count; ++i) v[i] = shape.vertices[f.v[i]];
    polys.clear();
    subdividePolygon(v, f.count, lightPatchSize, polys);
    for (const auto& poly : polys) {
      for (size_t k = 1; k + 1 < poly.size(); ++k) {  // fan: quads become two triangles
        const Vec3d tri[3] = {poly[0], poly[k], poly[k + 1]};
        const Vec3d n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
        const double area = 0.5 * glm::length(n);
        for (const Vec3d& p : tri) {
          Acc& a = acc[vertex(p)];
          a.area += area;
          a.normal += n;  // |n| = 2·area: area-weighted
        }
      }
    }
  }
  for (size_t i = 0; i < positions.size(); ++i) {
    LightSample s;
    s.kind = LightSampleKind::AreaVertex;
    s.light = lightIndex;
    s.position = Vec3(positions[i]);
    s.normal = Vec3(glm::normalize(acc[i].normal));
    s.emission = le;
    s.weight = static_cast<float>(acc[i].area / 3.0);
    out.push_back(s);
  }
}

}  // namespace

std::vector<LightSample> makeLightSamples(const SceneDesc& scene, const std::vector<uint32_t>& lights,
                                          double lightPatchSize) {
  std::vector<LightSample> out;
  for (uint32_t li : lights) {
    const LightDesc& l = scene.lights[li];
    LightSample s;
    s.light = li;
    switch (l.type) {
      case LightType::Point:
        s.kind = LightSampleKind::Point, s.position = Vec3(l.position), s.emission = l.power;
        out.push_back(s);
        break;
      case LightType::Spot:
        s.kind = LightSampleKind::Spot, s.position = Vec3(l.position), s.normal = Vec3(l.direction);
        s.emission = l.power;
        out.push_back(s);
        break;
      case LightType::Directional:
        s.kind = LightSampleKind::Directional, s.normal = Vec3(l.direction), s.emission = l.irradiance;
        out.push_back(s);
        break;
      case LightType::Area:
        areaSamples(scene, li, lightPatchSize > 0 ? lightPatchSize : 0.02, out);  // FIXME automatic tessellation
        break;
    }
  }
  return out;
}

}  // namespace fs
