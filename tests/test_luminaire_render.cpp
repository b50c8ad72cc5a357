// Luminaires in the path tracer (render/lights/luminaires.h): the exit patches sampled from outside a luminaire's
// box and seen through, its lights suppressed past a counted entry. The image must be the one the same table gives
// with the luminaires' lights as ordinary lights (--luminaires off), per 8×8 block within 3σ (σ from the per-pass
// block means), on a bulb in an open metal bowl, a filament in a clear glass envelope, and a point light in a box
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

/// The scene with its first-shot table (Embree item buffers, R = 64, luminaires found at the defaults).
RenderScene withTable(const SceneDesc& d) {
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  po.luminaires.particles = 1u << 19;
  return RenderScene(d, preprocessScene(d, po));
}

/// The exit distribution holds every bounce inside the luminaire's box, which a path's max depth would cut: paths
/// long enough that what they cut is far below the tests' σ (0.7^32 ≈ 1e-5).
IntegratorOptions pathOptions(const SceneDesc&, bool luminaires) {
  IntegratorOptions io;
  io.maxDepth = 32;
  io.luminaires = luminaires;
  return io;
}

/// Path tracing with the luminaires (@p passes) against path tracing with their lights as lights (@p passesOff).
void expectSameImage(const std::string& name, const RenderScene& scene, int passes, int passesOff) {
  ASSERT_FALSE(scene.firstShot()->luminaires.empty()) << name << ": no luminaire found";
  auto on = makeIntegrator("path", pathOptions(scene.desc(), true));
  auto off = makeIntegrator("path", pathOptions(scene.desc(), false));
  on->preprocess(scene);
  off->preprocess(scene);
  test::expectBlocksAgree(name, test::blockMeans(*on, scene, passes), test::blockMeans(*off, scene, passesOff, 2));
}

/// A point light (2 W) in a 30 cm box of grey diffuse walls whose face towards the camera is open, on a stand in the
/// hidden-lights room; the camera looks into the opening from 0.8 m.
SceneDesc openBox() {
  SceneDesc d = test::hiddenLightsRoom(
      R"("shade": {"type": "diffuse", "albedo": 0.6})",
      R"({"type": "quad", "material": "shade", "vertices": [[1.0,0.8,0.6],[1.3,0.8,0.6],[1.3,0.8,0.9],[1.0,0.8,0.9]]},
         {"type": "quad", "material": "shade", "vertices": [[1.0,1.1,0.6],[1.0,1.1,0.9],[1.3,1.1,0.9],[1.3,1.1,0.6]]},
         {"type": "quad", "material": "shade", "vertices": [[1.0,0.8,0.6],[1.0,0.8,0.9],[1.0,1.1,0.9],[1.0,1.1,0.6]]},
         {"type": "quad", "material": "shade", "vertices": [[1.3,0.8,0.6],[1.3,1.1,0.6],[1.3,1.1,0.9],[1.3,0.8,0.9]]},
         {"type": "quad", "material": "shade", "vertices": [[1.0,0.8,0.6],[1.0,1.1,0.6],[1.3,1.1,0.6],[1.3,0.8,0.6]]}],
    "lights": [{"type": "point", "position": [1.15, 0.95, 0.7], "power": 2})");
  d.camera.position = Vec3d(1.35, 1.05, 1.6);
  d.camera.lookAt = Vec3d(1.15, 0.95, 0.75);
  d.camera.fovYDeg = 60;
  return d;
}

}  // namespace

TEST(LuminaireRender, BowlLampAsWithItsLightsAsLights) {
  const SceneDesc d = test::bowlLamp();
  expectSameImage("bowl lamp", withTable(d), 800, 4000);
}

TEST(LuminaireRender, GlassBulbAsWithItsLightsAsLights) {
  const SceneDesc d = test::glassBulb();
  expectSameImage("glass bulb", withTable(d), 300, 1500);
}

// The camera looks into the box: its inside is seen as it is (the light's direct light there, the walls'
// interreflections), the room around it through the exit patches.
TEST(LuminaireRender, OpenBoxSeenInsideAsItIs) {
  const SceneDesc d = openBox();
  expectSameImage("open box", withTable(d), 600, 2000);
}

// Where no shadow ray reaches the light (behind glass) the exit patches are what the path tracer samples: the mean
// pixel variance per pass with the luminaire must be below the one without (3σ apart).
TEST(LuminaireRender, GlassBulbLessNoisy) {
  const SceneDesc d = test::glassBulb();
  const RenderScene scene = withTable(d);
  ASSERT_FALSE(scene.firstShot()->luminaires.empty());
  auto on = makeIntegrator("path", pathOptions(d, true)), off = makeIntegrator("path", pathOptions(d, false));
  on->preprocess(scene);
  off->preprocess(scene);
  const test::Moments von = test::pixelVariance(*on, scene, 60), voff = test::pixelVariance(*off, scene, 60);
  fmt::print("glass bulb, mean pixel variance per pass: luminaire {:.4g} ± {:.2g}, lights as lights {:.4g} ± {:.2g}\n",
             von.mean(), von.se(), voff.mean(), voff.se());
  EXPECT_LT(von.mean() + 3.0 * std::hypot(von.se(), voff.se()), voff.mean());
}
