#include "preprocess/light_samples.h"

#include "common/util/progress.h"
#include "preprocess/light_tessellation.h"
#include "preprocess/sphere_light.h"

namespace firstshot {

namespace {

/// Vertex samples of one emissive shape (preprocess/light_tessellation.h).
void areaSamples(const SceneDesc& scene, uint32_t lightIndex, double lightPatchSize, double lightTolerance,
                 std::vector<LightSample>& out) {
  const LightDesc& light = scene.lights[lightIndex];
  const Color le = scene.materials[scene.shapes[light.shape].material].emission;
  const LightTessellation t = tessellateAreaLight(scene, light.shape, lightPatchSize, lightTolerance, kLightSampleBudget, true);
  if (lightPatchSize <= 0) {  // automatic: a sphere as isotropic samples inside it where they do (sphere_light.h)
    const std::vector<LightSample> sphere = sphereLightSamples(scene, lightIndex, lightTolerance, t.tolerance);
    if (!sphere.empty()) return out.insert(out.end(), sphere.begin(), sphere.end()), void();
    reportRelaxed(scene, light.shape, t, lightTolerance);
  }
  for (size_t i = 0; i < t.positions.size(); ++i) {
    LightSample s;
    s.kind = LightSampleKind::AreaVertex;
    s.light = lightIndex;
    s.position = Vec3(t.positions[i]);
    s.normal = Vec3(t.normals[i]);
    s.emission = t.emission.empty() ? le : t.emission[i];  // a textured emitter's per sample
    s.weight = static_cast<float>(t.weights[i]);
    out.push_back(s);
  }
}

}  // namespace

std::vector<LightSample> makeLightSamples(const SceneDesc& scene, const std::vector<uint32_t>& lights,
                                          double lightPatchSize, double lightTolerance, bool quiet) {
  std::vector<LightSample> out;
  uint64_t faces = 0;  // the area lights' faces: the unit of the tessellation's progress
  for (uint32_t li : lights)
    if (scene.lights[li].type == LightType::Area) faces += scene.shapes[scene.lights[li].shape].faces.size();
  Progress progress("area-light samples", faces, quiet || faces == 0);
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
        areaSamples(scene, li, lightPatchSize, lightTolerance, out);
        progress.advance(scene.shapes[l.shape].faces.size());
        break;
    }
  }
  return out;
}

}  // namespace firstshot
