// The sun through a window: a directional light's factors resolve a window's shadow on patches that
// its scene-wide window draws smaller than a pixel (a ground plane 200 m wide makes those pixels
// nearly a metre wide).
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/table/firstshot.h"
#include "preprocess/preprocessor.h"
#include "render_util.h"
#include "test_util.h"

namespace firstshot {
namespace {

constexpr double kE = 5.0;  // the sun's irradiance on a plane facing it, W/m²

/// A closed 4 × 3 × 4 m room on a 200 m ground plane, a 1 × 1 m opening in its x = 0 wall (y and z
/// in [1.5, 2.5]), and the sun travelling along (sin 30°, −cos 30°, 0): through the opening it falls
/// on the floor only, at x in [0.87, 1.44].
SceneDesc roomWithWindow() {
  const char* wall = R"({{"type": "quad", "material": "m", "vertices": [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}], [{}, {}, {}]]}})";
  auto quad = [&](double ax, double ay, double az, double bx, double by, double bz, double cx, double cy, double cz, double dx,
                  double dy, double dz) { return fmt::format(fmt::runtime(wall), ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz); };
  std::string shapes = fmt::format(R"({{"type": "quad", "material": "floor", "vertices": [[0, 0, 0], [0, 0, 4], [4, 0, 4], [4, 0, 0]]}})");
  shapes += "," + quad(0, 3, 0, 4, 3, 0, 4, 3, 4, 0, 3, 4);           // ceiling
  shapes += "," + quad(4, 0, 0, 4, 0, 4, 4, 3, 4, 4, 3, 0);           // x = 4
  shapes += "," + quad(0, 0, 0, 4, 0, 0, 4, 3, 0, 0, 3, 0);           // z = 0
  shapes += "," + quad(0, 0, 4, 0, 3, 4, 4, 3, 4, 4, 0, 4);           // z = 4
  shapes += "," + quad(0, 0, 0, 0, 3, 0, 0, 3, 1.5, 0, 0, 1.5);       // x = 0, around the opening
  shapes += "," + quad(0, 0, 2.5, 0, 3, 2.5, 0, 3, 4, 0, 0, 4);
  shapes += "," + quad(0, 0, 1.5, 0, 1.5, 1.5, 0, 1.5, 2.5, 0, 0, 2.5);
  shapes += "," + quad(0, 2.5, 1.5, 0, 3, 1.5, 0, 3, 2.5, 0, 2.5, 2.5);
  shapes += "," + quad(-100, -0.01, -100, -100, -0.01, 100, 100, -0.01, 100, 100, -0.01, -100);  // the ground
  return test::sceneFromJson(fmt::format(R"({{
    "materials": {{"m": {{"type": "diffuse", "albedo": 0.5}}, "floor": {{"type": "diffuse", "albedo": 0.5}}}},
    "shapes": [{}],
    "lights": [{{"type": "directional", "direction": [0.5, {:.17g}, 0], "irradiance": {}}}]}})",
                                         shapes, -std::sqrt(0.75), kE));
}

// The power on the floor is the sun's through the opening, E⊥ · 1 m² · cos 60° (the floor is the
// first shape), within 1%, and none of it away from the sun's patch. Deciding each patch smaller than
// the sun window's pixel by its centroid alone left this floor dark.
TEST(SunThroughAWindow, TheFloorReceivesThePowerThroughTheOpening) {
  const SceneDesc desc = roomWithWindow();
  for (const char* backend : {"gl", "embree"}) {
    PreprocessOptions po = defaultOptions(desc);
    po.settings.backend = backend;
    po.quiet = true;
    const FirstShotTable t = preprocessScene(desc, po);
    double floorPower = 0, outsideFloor = 0;
    for (uint32_t j = 0; j < t.mesh.size(); ++j) {
      const Patch& p = t.mesh.patches[j];
      if (p.shape != 0) continue;
      const double power = t.irradiance(j).x * p.area;
      floorPower += power;
      const bool beneath = p.centroid.x > 0.7 && p.centroid.x < 1.6 && p.centroid.z > 1.3 && p.centroid.z < 2.7;
      if (!beneath) outsideFloor += power;
    }
    const double expected = kE * 1.0 * 0.5;
    EXPECT_NEAR(floorPower, expected, 0.01 * expected) << backend;
    EXPECT_NEAR(outsideFloor, 0.0, 0.005 * expected) << backend << ": light on floor patches away from the sun's patch";
  }
}

}  // namespace
}  // namespace firstshot
