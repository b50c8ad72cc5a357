// The lit first-shot patches as light sources (patch_emitters.h).
#include "render/firstshot/patch_emitters.h"

#include <algorithm>
#include <cmath>

#include "common/sampling/sampling.h"

namespace firstshot {

Vec3 samplePatchPoint(const Patch& p, Vec2 u) {
  // Quads are split along v0–v2 and one of the two triangles chosen by area.
  const Vec3 *a = &p.v[0], *b = &p.v[1], *c = &p.v[2];
  if (p.count == 4) {
    const float a0 = glm::length(glm::cross(p.v[1] - p.v[0], p.v[2] - p.v[0]));
    const float a1 = glm::length(glm::cross(p.v[2] - p.v[0], p.v[3] - p.v[0]));
    const float f = a0 / (a0 + a1);
    if (u.x < f) {
      u.x = std::min(u.x / f, 0x1.fffffep-1f);
    } else {
      u.x = std::min((u.x - f) / (1.0f - f), 0x1.fffffep-1f);
      b = &p.v[2], c = &p.v[3];
    }
  }
  const Vec3 bary = squareToUniformTriangle(u);
  return bary.x * *a + bary.y * *b + bary.z * *c;
}

float patchSidePower(const RenderScene& scene, const std::vector<Color>& sideIrradiance, uint32_t j, uint32_t side) {
  const Patch& p = scene.mesh().patches[j];
  const BSDF& bsdf = scene.patchBsdf(j);
  // The material's own roughness bounds the textured one from above: below the table's it is polished everywhere.
  if (bsdf.hasDelta() || scene.bsdf(p.material).tooSharpForTable()) return 0.0f;
  Color E = sideIrradiance[2 * size_t(j) + side];
  if (bsdf.hasTransmission()) E += sideIrradiance[2 * size_t(j) + 1 - side];  // rough glass: shines through
  const Color phi = bsdf.albedo() * E * float(p.area);
  return (phi.x + phi.y + phi.z) * (1.0f / 3.0f);
}

bool patchPointExposed(const RenderScene& scene, uint32_t j, const Vec3& y, const Vec3& w) {
  const float scale = std::max({1.0f, std::abs(y.x), std::abs(y.y), std::abs(y.z)});
  // m: twice the renderer's ray offset (EmbreeScene's eps), far above y's rounding (about 10⁻⁷·scale), and
  // small enough that the paths it loses (y within h of a surface that its ray meets first) do not show.
  const float h = 2e-5f * scale;
  Hit hit;
  // Nothing met (rounding at the patch's very edge, a grazing w): the point counts as exposed.
  if (!scene.intersect(Ray(y + h * w, -w, 0.0f, 2.0f * h), hit)) return true;
  return hit.patch == j;
}

bool mayBePolished(const RenderScene& scene) {
  const std::vector<MaterialDesc>& materials = scene.desc().materials;
  for (size_t m = 0; m < materials.size(); ++m)
    if (scene.bsdf(uint32_t(m)).tooSharpForTable() ||
        (materials[m].type == MaterialType::Pbr && materials[m].metallicRoughnessTexture))
      return true;
  return false;
}

Color patchRadiance(const RenderScene& scene, const FirstShotLighting& lighting, uint32_t j, const Vec3& y,
                    const Vec3& w) {
  const Patch& p = scene.mesh().patches[j];
  Hit hit;
  hit.p = y;
  hit.ng = p.normal;
  hit.patch = j;
  const BSDF bsdf = scene.bsdfAt(hit);  // the texture at y itself
  if (bsdf.tooSharpForTable()) return Color(0.0f);  // a polished point: its reflection is not the table's
  const Frame frame = scene.shadingFrame(hit);  // as the path walk's first-shot term at y
  return lighting.eval(hit, frame, frame.toLocal(w), bsdf);
}

}  // namespace firstshot
