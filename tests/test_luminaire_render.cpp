// Luminaires in the path tracer and in light tracing (render/lights/luminaires.h): the exit patches sampled from
// outside a luminaire's box and seen through, its lights suppressed past a counted entry; exit particles, and inner
// particles that end where they leave the box. The images must be the one the same table gives with the luminaires'
// lights as ordinary lights (--luminaires off), per 8×8 block within 3σ (σ from the per-pass block means), on a bulb in an open metal bowl, a filament in a clear glass envelope, and a point light in a box
// with one opening that the camera looks into (what it sees inside must be what is there); and it must be less
// noisy per sample where the light hides (the mean pixel variance, σ from the samples).
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>

#include "preprocess/preprocessor.h"
#include "tests/block_compare.h"
#include "tests/hidden_lights_scenes.h"
#include "tests/test_util.h"

using namespace fs;

namespace {

/// The exit distribution holds every bounce inside the luminaire's box, which a path's max depth would cut: paths
/// long enough that what they cut is far below the tests' σ (0.7^32 ≈ 1e-5).
IntegratorOptions pathOptions(const SceneDesc&, bool luminaires) {
  IntegratorOptions io;
  io.maxDepth = 32;
  io.luminaires = luminaires;
  return io;
}

/// Path tracing (@p pathPasses) and light tracing (@p lightPasses) with the luminaires against light tracing with
/// their lights as lights (@p refPasses), the least noisy reference in these rooms (the path tracer's blocks without
/// the luminaires have heavy tails behind glass: their σ from a few thousand passes is not to be trusted there).
void expectSameImage(const std::string& name, const RenderScene& scene, int pathPasses, int lightPasses,
                     int refPasses) {
  ASSERT_FALSE(scene.firstShot()->luminaires.empty()) << name << ": no luminaire found";
  auto ref = makeIntegrator("light", pathOptions(scene.desc(), false));
  ref->preprocess(scene);
  const std::vector<test::Moments> refBlocks = test::blockMeans(*ref, scene, refPasses, 2);
  for (const auto& [integrator, passes] : {std::pair{"path", pathPasses}, std::pair{"light", lightPasses}}) {
    auto on = makeIntegrator(integrator, pathOptions(scene.desc(), true));
    on->preprocess(scene);
    test::expectBlocksAgree(name + ", " + integrator + " with the luminaires against light without",
                            test::blockMeans(*on, scene, passes), refBlocks);
  }
}

}  // namespace

TEST(LuminaireRender, BowlLampAsWithItsLightsAsLights) {
  const SceneDesc d = test::bowlLamp();
  expectSameImage("bowl lamp", test::withLuminaireTable(d), 300, 150, 300);
}

TEST(LuminaireRender, GlassBulbAsWithItsLightsAsLights) {
  const SceneDesc d = test::glassBulb();
  expectSameImage("glass bulb", test::withLuminaireTable(d), 300, 300, 300);
}

// The camera looks into the box: its inside is seen as it is (the light's direct light there, the walls'
// interreflections), the room around it through the exit patches.
TEST(LuminaireRender, OpenBoxSeenInsideAsItIs) {
  const SceneDesc d = test::openBox();
  expectSameImage("open box", test::withLuminaireTable(d), 400, 150, 300);
}

// Where no shadow ray reaches the light (behind glass) the exit patches are what the path tracer samples: the mean
// pixel variance per pass with the luminaire must be below the one without (3σ apart).
TEST(LuminaireRender, GlassBulbLessNoisy) {
  const SceneDesc d = test::glassBulb();
  const RenderScene scene = test::withLuminaireTable(d);
  ASSERT_FALSE(scene.firstShot()->luminaires.empty());
  auto on = makeIntegrator("path", pathOptions(d, true)), off = makeIntegrator("path", pathOptions(d, false));
  on->preprocess(scene);
  off->preprocess(scene);
  const test::Moments von = test::pixelVariance(*on, scene, 60), voff = test::pixelVariance(*off, scene, 60);
  fmt::print("glass bulb, mean pixel variance per pass: luminaire {:.4g} ± {:.2g}, lights as lights {:.4g} ± {:.2g}\n",
             von.mean(), von.se(), voff.mean(), voff.se());
  EXPECT_LT(von.mean() + 3.0 * std::hypot(von.se(), voff.se()), voff.mean());
}

// The shipped fixture room (scenes/fixture-room.json): 14 bulbs in a cove under a shelf along the walls and 3 lamps
// in shades open at top and bottom, each found as a luminaire at the defaults. At 32 × 24, path tracing with them
// against light tracing without (σ from the passes).
TEST(LuminaireRender, FixtureRoomCovesAndShades) {
  SceneDesc d = loadScene(test::source("scenes/fixture-room.json"));
  d.camera.width = 32, d.camera.height = 24;
  const RenderScene scene = test::withLuminaireTable(d);
  EXPECT_GE(scene.firstShot()->luminaires.size(), 10u) << "the cove's bulbs and the lamps are luminaires";
  auto ref = makeIntegrator("light", pathOptions(d, false)), on = makeIntegrator("path", pathOptions(d, true));
  ref->preprocess(scene);
  on->preprocess(scene);
  test::expectBlocksAgree("fixture room, path with the luminaires against light without", test::blockMeans(*on, scene, 1500),
                          test::blockMeans(*ref, scene, 200, 2));
}
