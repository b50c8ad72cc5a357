// The automatic coarse patch size.
#include "common/patches/patch_size.h"

#include <algorithm>
#include <cmath>

#include "common/patches/patches.h"

namespace firstshot {

namespace {

/// The longest edge (m) of any non-emissive face: the size at which every face is one patch.
double longestEdge(const SceneDesc& scene) {
  double longest = 0;
  for (const ShapeDesc& s : scene.shapes) {
    if (scene.materials[s.material].isEmissive()) continue;
    for (const Face& f : s.faces)
      for (int i = 0; i < f.count; ++i)
        longest = std::max(longest, glm::length(s.vertices[f.v[(i + 1) % f.count]] - s.vertices[f.v[i]]));
  }
  return longest;
}

}  // namespace

double autoPatchSize(const SceneDesc& scene, double budget) {
  const double top = longestEdge(scene);
  if (!(top > 0)) return 1.0;  // no surface to cut: any size gives the same (empty) mesh
  const double target = countPatchPolygons(scene, kFacesAsTheyAre) + budget;
  // The count falls monotonically as the size grows. Bisect on the size relative to the longest
  // edge (so a scaled scene takes the same steps), keeping `hi` a size whose count is within target.
  double lo = 0, hi = 1;  // fractions of `top`; count(lo·top) > target (or lo = 0), count(hi·top) ≤ target
  for (int step = 0; step < 64; ++step) {
    const double mid = lo > 0 ? std::sqrt(lo * hi) : hi / 2;
    if (countPatchPolygons(scene, mid * top) <= target)
      hi = mid;
    else
      lo = mid;
    if (lo > 0 && hi / lo < 1 + 1e-9) break;
  }
  // Just above the step of the count found: a rounding of the scaled coordinates cannot cross it.
  return std::min(1.0, hi * (1 + 1e-7)) * top;
}

void resolvePatchSizes(const SceneDesc& scene, FirstShotSettings& settings) {
  if (!(settings.patchSize > 0)) settings.patchSize = autoPatchSize(scene);
  settings.minPatchSize = settings.minPatchSize > 0 ? std::min(settings.minPatchSize, settings.patchSize)
                                                    : settings.patchSize / kDefaultRefineRatio;
}

double resolvePatchSize(const SceneDesc& scene) {
  FirstShotSettings settings = scene.settings;  // the scene's preprocess settings (SettingsDesc is one)
  resolvePatchSizes(scene, settings);
  return settings.patchSize;
}

}  // namespace firstshot
