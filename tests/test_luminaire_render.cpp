// Luminaires in the path tracer and in light tracing (render/scene/luminaire_boxes.h): the exit patches sampled from
// outside a luminaire's box and seen through, its lights suppressed past a counted entry; exit particles, and inner
// particles that end where they leave the box. The images must be the one the same table gives with the luminaires'
// lights as ordinary lights (--luminaires off), per 8×8 block within 3σ (σ from the per-pass block means), on a bulb in an open metal bowl, a filament in a clear glass envelope, and a point light in a box
// with one opening that the camera looks into (what it sees inside must be what is there); and it must be less
// noisy per sample where the light hides (the mean pixel variance, σ from the samples).
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "tests/block_compare.h"
#include "tests/hidden_lights_scenes.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// The exit distribution holds every bounce inside the luminaire's box, which a path's max depth would cut: paths
/// long enough that what they cut is far below the tests' σ (0.7^32 ≈ 1e-5). Light tracing and BDPT split every
/// luminaire's light at its box (@p everySplit), not only where that pays: the split is what these images check.
IntegratorOptions pathOptions(const SceneDesc&, bool luminaires, bool everySplit = true) {
  IntegratorOptions io;
  io.maxDepth = 32;
  io.luminaires = luminaires;
  io.splitEveryLuminaire = everySplit;
  return io;
}

/// Path tracing (@p pathPasses), light tracing (@p lightPasses) and BDPT (@p bdptPasses: its light subpaths and samples
/// leave the exit patches, its luminaires' lights make only the paths no exit patch makes) with the luminaires against
/// light tracing with
/// their lights as lights (@p refPasses), the least noisy reference in these rooms (the path tracer's blocks without
/// the luminaires have heavy tails behind glass: their σ from a few thousand passes is not to be trusted there).
/// @p knownBias: the exit table's own error allowed beside the noise (block_compare.h).
void expectSameImage(const std::string& name, const RenderScene& scene, int pathPasses, int lightPasses,
                     int refPasses, int bdptPasses, double knownBias = 0.0) {
  ASSERT_FALSE(scene.firstShot()->luminaires.empty()) << name << ": no luminaire found";
  auto ref = makeIntegrator("light", pathOptions(scene.desc(), false));
  ref->preprocess(scene);
  const std::vector<test::Moments> refBlocks = test::blockMeans(*ref, scene, refPasses, 2);
  for (const auto& [integrator, passes] :
       {std::pair{"path", pathPasses}, std::pair{"light", lightPasses}, std::pair{"bdpt", bdptPasses}}) {
    auto on = makeIntegrator(integrator, pathOptions(scene.desc(), true));
    on->preprocess(scene);
    test::expectBlocksAgree(name + ", " + integrator + " with the luminaires against light without",
                            test::blockMeans(*on, scene, passes), refBlocks, knownBias);
  }
}

}  // namespace

TEST(LuminaireRender, BowlLampAsWithItsLightsAsLights) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireRender.GlassBulbAsWithItsLightsAsLights and OpenBoxSeenInsideAsItIs");
  const SceneDesc d = test::bowlLamp();
  expectSameImage("bowl lamp", test::withLuminaireTable(d), 300, 150, 300, 150);
}

TEST(LuminaireRender, GlassBulbAsWithItsLightsAsLights) {
  const SceneDesc d = test::glassBulb();
  expectSameImage("glass bulb", test::withLuminaireTable(d), 300, 300, 300, 300);
}

// A frosted envelope (rough glass, roughness 0.5): its light leaves after a non-delta bounce, so the exit table holds
// it (a clear one's is the specular light). The table's patch × bin blur is what it is beside the box: light tracing
// with the luminaire measured +4.6% and +3.0% in two blocks at 300 passes, and at 64 × 48, 1024 spp, +11% in the block
// of the ceiling 0.2 m above the box (the image mean within 0.1%), so 5% is allowed beside the noise. The camera sees
// the envelope, which the path tracer finds noisy: 1500 passes.
TEST(LuminaireRender, FrostedBulbAsWithItsLightsAsLights) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireRender.GlassBulbAsWithItsLightsAsLights");
  const RenderScene scene = test::withLuminaireTable(test::glassBulb(0.5));
  ASSERT_EQ(scene.firstShot()->luminaires.size(), 1u) << "the frosted envelope is a luminaire";
  const Luminaire& lum = scene.firstShot()->luminaires[0];
  EXPECT_GT(test::gray(lum.exitPower), 0.5 * test::gray(lum.power)) << "most of its light in the exit table";
  expectSameImage("frosted bulb", scene, 1500, 300, 300, 300, 0.05);
}

// The camera looks into the box: its inside is seen as it is (the light's direct light there, the walls'
// interreflections), the room around it through the exit patches. The room right beside the box gets the exit
// table's patch × bin blur: light tracing with the luminaire (σ 1.5% per block, the least noisy here) measured its
// worst block −2.7%, −2.7%, −3.2%, −3.9% for four tracing seeds at 2^19 particles and −3.4% at 2^21 (it does not
// shrink with the particles: not their noise), so 4% is allowed beside the noise.
TEST(LuminaireRender, OpenBoxSeenInsideAsItIs) {
  const SceneDesc d = test::openBox();
  expectSameImage("open box", test::withLuminaireTable(d), 400, 150, 300, 150, 0.04);
}

// A spot light aimed at the open box's back wall, the camera beside the box looking past it: no light leaves straight
// and the inside is hidden, so light tracing and BDPT split the luminaire at the share measured on the picture (the
// lights 5% of its particles' choice weight: test_luminaire_light_tracing.cpp, SplitWhereItPays), against light
// tracing without the luminaire, beside the exit table's blur (4%, as above).
TEST(LuminaireRender, SplitAsMeasuredAsWithItsLightAsALight) {
  SceneDesc d = test::openBox();
  d.camera = test::openBox(false, true).camera;  // beside the box, looking past it (no glass ball here)
  d.lights[0].type = LightType::Spot;
  d.lights[0].direction = Vec3d(0, 0, -1);
  const RenderScene scene = test::withLuminaireTable(d);
  auto ref = makeIntegrator("light", pathOptions(d, false));
  ref->preprocess(scene);
  const std::vector<test::Moments> refBlocks = test::blockMeans(*ref, scene, 600, 2);
  for (const char* integrator : {"light", "bdpt"}) {
    auto on = makeIntegrator(integrator, pathOptions(d, true, false));
    on->preprocess(scene);
    test::expectBlocksAgree(std::string("spot in the open box, ") + integrator +
                                " split as measured against light without",
                            test::blockMeans(*on, scene, 600), refBlocks, 0.04);
  }
}

// A glass ball in the light that leaves the open box, outside its box: what the ball focuses on the wall behind it is
// found by paths from the wall through the glass into the box, a box entered from a delta vertex after a non-delta
// one, inside which the light is met as it is (its exit light is no part of a path through glass). The path tracer
// and BDPT with the luminaire against light tracing without, beside the exit table's blur by the box (4%, as above).
TEST(LuminaireRender, LightThroughGlassOutsideTheBox) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireRender.OpenBoxSeenInsideAsItIs");
  const SceneDesc d = test::openBox(false, true);
  const RenderScene scene = test::withLuminaireTable(d);
  ASSERT_EQ(scene.firstShot()->luminaires.size(), 1u);
  const Luminaire& lum = scene.firstShot()->luminaires[0];
  ASSERT_LT(lum.hi.z, 1.3 - 0.12) << "the ball is outside the box";
  auto on = makeIntegrator("path", pathOptions(d, true)), ref = makeIntegrator("light", pathOptions(d, false));
  auto bdpt = makeIntegrator("bdpt", pathOptions(d, true));
  on->preprocess(scene);
  ref->preprocess(scene);
  bdpt->preprocess(scene);
  const std::vector<test::Moments> refBlocks = test::blockMeans(*ref, scene, 300, 2);
  test::expectBlocksAgree("light through glass outside the box, path with the luminaire against light without",
                          test::blockMeans(*on, scene, 600), refBlocks, 0.04);
  // BDPT: what leaves the box and passes the ball is the exit patches' where a non-delta hit follows the box (the
  // wall), its lights' where none can be joined (the camera seeing the box's inside through the ball).
  test::expectBlocksAgree("light through glass outside the box, bdpt with the luminaire against light without",
                          test::blockMeans(*bdpt, scene, 300), refBlocks, 0.04);
}

// The ceiling straight above the bowl of the shipped bowl-lamp room (scenes/bowl-lamp-room.json), where its hot spot
// is: an 8° view of it (16 × 16 pixels, four blocks) with the luminaire against light tracing with the bulb as a light.
// The bulb's direct light through the opening is sampled from the bulb itself (the exit table holds only what the bowl
// reflects); through the table it came out 22% too dark here (the direction bins around the face's normal:
// docs/luminaires.md, "Error of the table"; 4.0σ beyond the allowance below). The bowl's reflection still passes
// the table, −8% measured there (20° view, 2048 spp; cause not found), so 10% is allowed beside the noise.
TEST(LuminaireRender, CeilingAboveTheBowlAsWithItsLightAsALight) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireRender.GlassBulbAsWithItsLightsAsLights and OpenBoxSeenInsideAsItIs");
  SceneDesc d = loadScene(test::source("scenes/bowl-lamp-room.json"));
  d.camera.position = Vec3d(3.4, 2.0, 1.0);
  d.camera.lookAt = Vec3d(3.0, 3.0, 1.0);
  d.camera.fovYDeg = 8;
  d.camera.width = d.camera.height = 16;
  const RenderScene scene = test::withLuminaireTable(d);
  ASSERT_EQ(scene.firstShot()->luminaires.size(), 1u);
  auto on = makeIntegrator("path", pathOptions(d, true)), ref = makeIntegrator("light", pathOptions(d, false));
  on->preprocess(scene);
  ref->preprocess(scene);
  test::expectBlocksAgree("ceiling above the bowl, path with the luminaire against light without",
                          test::blockMeans(*on, scene, 400), test::blockMeans(*ref, scene, 800, 2), 0.10);
}

// Where no shadow ray reaches the light (behind glass) the exit patches are what the path tracer samples: the mean
// pixel variance per pass with the luminaire must be below the one without (3σ apart).
TEST(LuminaireRender, GlassBulbLessNoisy) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireRender.GlassBulbAsWithItsLightsAsLights");
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
// in shades open at top and bottom, each found as a luminaire at the defaults. At 32 × 24, path tracing and BDPT with
// them against light tracing without (σ from the passes), beside the exit table's own bias: the patch × direction
// bins blur the light the shades' insides send out, measured −1.25% in the lower right block (the largest; 8192
// against 3 × 4096 spp, docs/luminaires.md), so 2% of it is allowed beside the noise.
TEST(LuminaireRender, FixtureRoomCovesAndShades) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireRender.BowlLampAsWithItsLightsAsLights and OpenBoxSeenInsideAsItIs");
  SceneDesc d = loadScene(test::source("scenes/fixture-room.json"));
  d.camera.width = 32, d.camera.height = 24;
  const RenderScene scene = test::withLuminaireTable(d);
  EXPECT_GE(scene.firstShot()->luminaires.size(), 10u) << "the cove's bulbs and the lamps are luminaires";
  auto ref = makeIntegrator("light", pathOptions(d, false)), on = makeIntegrator("path", pathOptions(d, true));
  ref->preprocess(scene);
  on->preprocess(scene);
  const std::vector<test::Moments> refBlocks = test::blockMeans(*ref, scene, 200, 2);
  test::expectBlocksAgree("fixture room, path with the luminaires against light without", test::blockMeans(*on, scene, 1500),
                          refBlocks, 0.02);
  // BDPT: the camera sees into the coves and shades, whose insides its luminaires' lights light (no exit patch's path);
  // each luminaire split where that pays (render/integrators/common/luminaire_split.h), as a render does.
  auto bdpt = makeIntegrator("bdpt", pathOptions(d, true, false));
  bdpt->preprocess(scene);
  test::expectBlocksAgree("fixture room, bdpt with the luminaires against light without",
                          test::blockMeans(*bdpt, scene, 300), refBlocks, 0.02);
}

// A point light (100 W) at the centre of a clear glass sphere (r = 10 cm, ior 1.5) 2 m above a white floor: light
// leaves a lossless closed shell radially, as from the bare bulb, so the floor's radiance at (x, 0, z) is
// ρ/π · Φ/(4π) · cos θ/d² exactly. The path tracer samples it through the luminaire's specular light (an intensity
// about its centre). Points on the line z = 0 lay on the patch × bin table's bin edges (−78% to −99% before it had a
// specular part), the others between them (+10–13%). Allowed: 1% (measured: within 0.27%, the particles' numbers
// stratified; with independent ones an intensity bin's count was Poisson, √(kGonioBins/N) = 1.1%, and one point −1.8%).
TEST(LuminaireRender, GlassBulbLightsTheFloorAsTheBareBulb) {
  auto scene = [](double x, double z) {
    return test::sceneFromJson(fmt::format(R"({{"materials": {{"floor": {{"type": "diffuse", "albedo": 0.5}},
        "glass": {{"type": "dielectric", "ior": 1.5}}}},
      "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-10,0,-10],[-10,0,10],[10,0,10],[10,0,-10]]}},
                 {{"type": "sphere", "material": "glass", "center": [0, 2, 0], "radius": 0.1, "subdivisions": 5, "smooth": true}}],
      "lights": [{{"type": "point", "position": [0, 2, 0], "power": 100}}],
      "camera": {{"position": [{0}, 0.3, {1}], "look_at": [{0}, 0.0, {2}], "fov_y": 1, "resolution": [8, 8]}},
      "settings": {{"patch_size": 1.0, "max_depth": 1}}}})", x, z + 0.2, z));
  };
#ifdef FIRSTSHOT_UNDER_SANITIZERS
  const uint64_t particles = 1u << 18;  // allowed 3 × 4.4% more: it still catches the stripes (−78% and worse)
  const double frozen = std::sqrt(double(Luminaire::kGonioBins) / double(particles));
#else
  const uint64_t particles = 1u << 22;  // the default for one luminaire
  const double frozen = 0.0;
#endif
  const SceneDesc first = scene(0.0, 0.0);
  PreprocessOptions po = defaultOptions(first);
  po.settings.backend = "embree", po.quiet = true, po.luminaires.particles = particles;
  const FirstShotTable table = preprocessScene(first, po);  // the camera is not in the table
  ASSERT_EQ(table.luminaires.size(), 1u);
  EXPECT_NEAR(luminance(table.luminaires[0].specularPower), 100.0, 0.5) << "all of it through the glass";
  const double points[][2] = {{0.3, 0.0}, {1.0, 0.0}, {2.0, 0.0}, {1.0, 0.2}, {0.7, 0.55}, {1.5, -0.8}, {0.2, 0.9}};
  for (const auto& xz : points) {
    const RenderScene rs(scene(xz[0], xz[1]), table);
    IntegratorOptions io;
    io.maxDepth = 1;
    auto path = makeIntegrator("path", io);
    path->preprocess(rs);
    const test::RenderRun run = test::renderWith(*path, rs, 16);
    double mean = 0, se = 0;
    test::imageMean(run.film, 1, mean, se);
    const double d2 = 4.0 + xz[0] * xz[0] + xz[1] * xz[1];
    const double expected = 0.5 / kPi * 100.0 / (4.0 * kPi) * (2.0 / std::sqrt(d2)) / d2;
    fmt::print("floor at ({}, {}): {:.5f} ± {:.5f} W/(m² sr), bare bulb {:.5f} ({:+.2f}%)\n", xz[0], xz[1], mean, se,
               expected, 100.0 * (mean - expected) / expected);
    EXPECT_LT(std::abs(mean - expected), (0.01 + 3.0 * frozen) * expected + 3.0 * se)
        << "at (" << xz[0] << ", " << xz[1] << ")";
  }
}
