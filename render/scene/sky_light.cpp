// The scene's infinite light: a sky model baked into a lat-long map, or an environment map file (sky_light.h).
#include "render/scene/sky_light.h"

#include <algorithm>
#include <cmath>

#include "common/util/error.h"

namespace firstshot {

namespace {

constexpr int kSub = 4;  ///< points per texel and axis when baking a sky

}  // namespace

EnvironmentMap bakeSky(const SkyDesc& sky, int width, int height) {
  const Color ground(skyRadiance(sky.groundLuminance()));
  std::vector<Color> texels(size_t(width) * size_t(height), ground);
  for (int j = 0; j < height / 2; ++j) {  // the upper hemisphere: rows whose θ range lies above the horizon
    const double mu0 = std::cos(kPi * j / height), mu1 = std::cos(kPi * (j + 1) / height);
    for (int i = 0; i < width; ++i) {
      double sum = 0.0;
      for (int a = 0; a < kSub; ++a) {
        const double mu = mu0 + (mu1 - mu0) * (a + 0.5) / kSub, s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        for (int b = 0; b < kSub; ++b) {
          // environment_map.h's mapping: φ = (u − 0.5)·2π, direction (sin θ sin φ, cos θ, −sin θ cos φ).
          const double phi = ((i + (b + 0.5) / kSub) / width - 0.5) * 2.0 * kPi;
          sum += sky.dome.luminance(Vec3d(s * std::sin(phi), mu, -s * std::cos(phi)));
        }
      }
      texels[size_t(j) * width + i] = Color(skyRadiance(sum / (kSub * kSub)));
    }
  }
  return EnvironmentMap(std::move(texels), width, height);
}

std::shared_ptr<const EnvironmentMap> makeInfiniteLight(const SceneDesc& scene) {
  if (scene.sky) return std::make_shared<const EnvironmentMap>(bakeSky(*scene.sky));
  if (!scene.environment) return nullptr;
  const EnvironmentDesc& e = *scene.environment;
  if (e.file.empty())  // a constant environment: one radiance everywhere (any size gives the same light)
    return std::make_shared<const EnvironmentMap>(std::vector<Color>(8 * 4, e.constant), 8, 4, e.scale);
  try {
    return std::make_shared<const EnvironmentMap>(EnvironmentMap::load(e.file, e.scale, e.rotateDeg));
  } catch (const InputError& err) {
    throw InputError(scene.file, "environment.file", err.what());
  }
}

}  // namespace firstshot
