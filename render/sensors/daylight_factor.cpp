// The daylight factor's scene and summary (daylight_factor.h).
#include "render/sensors/daylight_factor.h"

#include <algorithm>
#include <memory>

#include "common/scene/sky_desc.h"
#include "common/util/error.h"

namespace firstshot {

DaylightFactorSetup daylightFactorScene(SceneDesc& scene) {
  if (!scene.sky || scene.sky->dome.type() != SkyType::CieOvercast)
    throw InputError(scene.file, "sky",
                     scene.sky ? "the daylight factor needs \"type\": \"cie-overcast\" (this sky is another model)"
                               : "the daylight factor needs a sky of \"type\": \"cie-overcast\" (the scene has none)");
  DaylightFactorSetup setup;
  for (const LightDesc& l : scene.lights)
    if (l.type != LightType::Area) setup.switchedOff.push_back(l.name);  // area lights: their materials, below
  scene.lights.clear();
  for (MaterialDesc& m : scene.materials) {
    if (!m.isEmissive()) continue;
    setup.switchedOff.push_back("material " + m.name);
    m.emission = Color(0.0f);
  }
  auto sky = std::make_shared<SkyDesc>(*scene.sky);
  sky->sunHorizontalLux = 0.0;  // the ground below the horizon: lit by the dome alone
  setup.outsideLux = sky->dome.horizontalIlluminance();
  scene.sky = std::move(sky);
  return setup;
}

DaylightFactorSummary summarizeDaylightFactor(const std::vector<SensorResult>& results, double outsideLux) {
  DaylightFactorSummary s;
  if (results.empty()) return s;
  std::vector<double> df;
  df.reserve(results.size());
  for (const SensorResult& r : results) df.push_back(daylightFactorPercent(r.lux, outsideLux));
  double sum = 0.0;
  for (double v : df) sum += v;
  s.avg = sum / double(df.size());
  const auto [lo, hi] = std::minmax_element(df.begin(), df.end());
  s.min = *lo;
  s.max = *hi;
  const size_t mid = df.size() / 2;
  std::nth_element(df.begin(), df.begin() + long(mid), df.end());
  s.median = df[mid];
  if (df.size() % 2 == 0) s.median = 0.5 * (s.median + *std::max_element(df.begin(), df.begin() + long(mid)));
  return s;
}

}  // namespace firstshot
