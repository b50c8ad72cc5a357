// The pilot of --integrator auto as functions (render/loop/integrator_pilot.h): its plan within 4% of the camera
// samples, its noise measure, the pixels it leaves out, how a fixed cost (the cache's fill) is charged, and which
// figure wins. The pilot as the renderer runs it: tests/test_integrator_auto.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>
#include <vector>

#include "render/integrators/irradiance_cache/cli.h"
#include "render/loop/integrator_pilot.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

TEST(IntegratorPilot, PlansItsImagesInFourPercentOfTheCameraSamples) {
  firstshot::CameraDesc cam;
  for (const auto& [w, h, spp, k] : std::vector<std::tuple<int, int, int, size_t>>{
           {512, 512, 64, 8}, {160, 120, 256, 4}, {128, 128, 1024, 8}, {1920, 1080, 16, 8}, {100, 300, 512, 4}}) {
    cam.width = w;
    cam.height = h;
    const firstshot::PilotPlan plan = firstshot::planPilot(cam, spp, k);
    SCOPED_TRACE(testing::Message() << w << "x" << h << " " << spp << " spp, " << k << " candidates");
    ASSERT_TRUE(plan.run);
    EXPECT_LE(double(plan.samples() * k), 0.04 * w * h * spp);  // the rest of 5% for what some take beyond
    EXPECT_LE(std::max(plan.width, plan.height), 48);
    EXPECT_GE(plan.spp, 4);
    EXPECT_NEAR(double(plan.width) / plan.height, double(w) / h, 0.05 * double(w) / h);  // the camera's aspect
  }
}

// A render sized by --time has the work of its seconds at the nominal ray rate (what a seeded preprocessing's share
// is taken of); the pilot's picture and samples do not change with it, and a render of given samples has none.
TEST(IntegratorPilot, ARenderGivenATimeHasTheWorkOfItsSecondsAtTheNominalRayRate) {
  firstshot::CameraDesc cam;
  cam.width = cam.height = 128;
  const firstshot::PilotPlan timed = firstshot::planPilot(cam, 305, 8, 20.0), counted = firstshot::planPilot(cam, 305, 8);
  EXPECT_DOUBLE_EQ(timed.renderWork, 20.0 * firstshot::kTimeRaysRate);
  EXPECT_EQ(counted.renderWork, 0.0);
  EXPECT_EQ(timed.width, counted.width);
  EXPECT_EQ(timed.height, counted.height);
  EXPECT_EQ(timed.spp, counted.spp);
}

TEST(IntegratorPilot, NoPilotWhereTheBudgetIsTooSmall) {
  firstshot::CameraDesc cam;
  cam.width = 32;
  cam.height = 32;
  EXPECT_FALSE(firstshot::planPilot(cam, 16, 8).run);   // 16 k camera samples: 5% is 51 per image
  EXPECT_FALSE(firstshot::planPilot(cam, 4096, 1).run); // one candidate: nothing to choose
  cam.width = cam.height = 256;
  EXPECT_TRUE(firstshot::planPilot(cam, 64, 4).run);
}

TEST(IntegratorPilot, NoiseIsTheRelativeRmsOfOneImage) {
  // Two images 1 + e and 1 − e per channel, mean 1: RMS((a − b)/√2) = 2e/√2 = e√2.
  const double e = 0.03;
  const std::vector<double> a(300, 1.0 + e), b(300, 1.0 - e);
  EXPECT_NEAR(firstshot::pilotNoise(a, b), e * std::sqrt(2.0), 1e-12);
  // Scale-free: ten times the light, the same relative noise.
  std::vector<double> a10(a), b10(b);
  for (double& v : a10) v *= 10.0;
  for (double& v : b10) v *= 10.0;
  EXPECT_NEAR(firstshot::pilotNoise(a10, b10), firstshot::pilotNoise(a, b), 1e-12);
  EXPECT_EQ(firstshot::pilotNoise(std::vector<double>(3, 0.0), std::vector<double>(3, 0.0)), 0.0);  // black: no figure
  // A lamp pixel 1000 and 2000 among 99 pixels of 1: both count as 5 m, m = (3000 + 198)/200 = 15.99.
  std::vector<double> lampA(100, 1.0), lampB(100, 1.0);
  lampA[0] = 1000.0;
  lampB[0] = 2000.0;
  EXPECT_EQ(firstshot::pilotNoise(lampA, lampB), 0.0);
  lampB[1] = 1.5;  // and one ordinary pixel's difference of 0.5 is what remains
  EXPECT_NEAR(firstshot::pilotNoise(lampA, lampB), std::sqrt(0.25 / 200.0) / ((3000.0 + 196.0 + 2.5) / 200.0), 1e-12);
}

// With the pixels the camera sees as they are left out (a lamp: 1000 and 2000), the rest counts unclamped: a firefly
// of 101 against 1 (every channel) among 99 pixels of 1. Kept values: 297 per image; mean (297 + 597)/594; the
// squared differences 3 · 100².
TEST(IntegratorPilot, LampsLeftOutFirefliesCountWhole) {
  std::vector<double> a(300, 1.0), b(300, 1.0);
  for (int c = 0; c < 3; ++c) a[size_t(c)] = 1000.0, b[size_t(c)] = 2000.0, b[size_t(3 + c)] = 101.0;
  std::vector<uint8_t> skip(100, 0);
  skip[0] = 1;
  const double mean = (297.0 + 597.0) / 594.0;
  EXPECT_NEAR(firstshot::pilotNoise(a, b, &skip), std::sqrt(30000.0 / 594.0) / mean, 1e-12);
  // Clamped at 5 m without the mask, the firefly counts far less.
  EXPECT_LT(firstshot::pilotNoise(a, b), 0.5 * firstshot::pilotNoise(a, b, &skip));
  // Everything left out: every pixel, clamped.
  std::vector<uint8_t> all(100, 1);
  EXPECT_EQ(firstshot::pilotNoise(a, b, &all), firstshot::pilotNoise(a, b));
  // The bulk's noise (clamp): the lamp left out and the firefly counted as 5 m, (5 m − 1)² in each channel.
  const double clamped = 5.0 * mean - 1.0;
  EXPECT_NEAR(firstshot::pilotNoise(a, b, &skip, true), std::sqrt(3.0 * clamped * clamped / (2.0 * 297.0)) / mean, 1e-12);
}

// A camera looking at a wall whose left half is a lamp and whose right half is plaster: the left pixels are seen as
// they are, the right ones are not; a pane in front of the wall is seen through.
TEST(IntegratorPilot, PixelsSeenAsTheyAreAreTheLampsAndMirrors) {
  const firstshot::SceneDesc d = firstshot::test::sceneFromJson(R"({"materials": {
      "plaster": {"type": "diffuse", "albedo": 0.5}, "lamp": {"type": "diffuse", "emission": 5},
      "pane": {"type": "thin_glass", "ior": 1.5}},
    "shapes": [{"type": "quad", "material": "lamp", "vertices": [[-1,-1,0],[0,-1,0],[0,1,0],[-1,1,0]]},
               {"type": "quad", "material": "plaster", "vertices": [[0,-1,0],[1,-1,0],[1,1,0],[0,1,0]]},
               {"type": "quad", "material": "pane", "vertices": [[-2,-2,1],[2,-2,1],[2,2,1],[-2,2,1]]}],
    "camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [8, 8]}})");
  const firstshot::RenderScene scene(d);
  const std::vector<uint8_t> skip = firstshot::pixelsSeenAsTheyAre(scene, d.camera);
  ASSERT_EQ(skip.size(), 64u);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(skip[size_t(8 * y + x)], x < 4 ? 1 : 0) << x << ", " << y;
}

TEST(IntegratorPilot, TheMostEfficientWins) {
  std::vector<firstshot::PilotFigure> f(3);
  f[0].efficiency = 1.0;
  f[1].efficiency = 3.0;
  f[2].efficiency = 3.0;
  EXPECT_EQ(firstshot::bestPilotFigure(f), 1u);  // the first of equals
}

// A figure that errs by more than its mean (Veach MIS: 1.3-25 at 2-4 passes) ranks only where it is one of the
// caller's robust candidates (the path tracer without the table, by either light sampler) and no figure of a method
// other than the path tracer ranks by its error: the classroom (0.75-2.2 at 4-5 passes, the cache outgrown) ranks
// its path tracers, veach-bidir (light tracing 0.5-0.8, the path tracer 1.2-1.7) does not rank the path tracer.
// Of the robust ones, only the one whose bulk (fireflies clamped) is the most efficient ranks.
TEST(IntegratorPilot, FiguresNoisierThanTheirMeansRankOnlyThePathTracerWithoutTheTable) {
  std::vector<firstshot::PilotFigure> f(4);
  for (size_t i = 0; i < f.size(); ++i)
    f[i].spp = 2, f[i].error = 1.4 + double(i), f[i].efficiency = f[i].bulkEfficiency = 1.0 + double(i);
  const std::vector<uint8_t> path = {1, 1, 1, 0};  // figure 3: light tracing, say
  EXPECT_EQ(firstshot::bestPilotFigure(f), 0u);    // nothing ranks: the first
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1}, path), 1u);
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1, 2}, path), 2u);  // the more efficient robust one, not light tracing (3)
  EXPECT_EQ(firstshot::bestPilotFigure(f, {2, 1}, path), 2u);
  EXPECT_EQ(firstshot::rankedPilotFigures(f, {1, 2}, path), (std::vector<uint8_t>{0, 0, 1, 0}));
  f[1].bulkEfficiency = 4.0;  // its fireflies aside, the other is the more efficient: it alone ranks
  EXPECT_EQ(firstshot::rankedPilotFigures(f, {1, 2}, path), (std::vector<uint8_t>{0, 1, 0, 0}));
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1, 2}, path), 1u);
  f[1].bulkEfficiency = 2.0;
  f[2].spp = 0, f[2].efficiency = 0.0;  // not measured: the other robust one
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1, 2}, path), 1u);
  f[2].spp = 2, f[2].efficiency = 3.0;
  f[0].error = 0.9;  // a path tracer with the table ranks by its error: the robust ones still rank beside it
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1, 2}, path), 2u);
  f[0].efficiency = 5.0;
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1, 2}, path), 0u);
  f[0].efficiency = 1.0;
  f[3].error = 0.9;  // light tracing ranks by its error: the robust ones do not rank by theirs
  EXPECT_EQ(firstshot::rankedPilotFigures(f, {1, 2}, path), (std::vector<uint8_t>{1, 0, 0, 1}));
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1, 2}, path), 3u);
  f[3].efficiency = 0.5;
  EXPECT_EQ(firstshot::bestPilotFigure(f, {1, 2}, path), 0u);
  f[3].error = 1.5, f[2].error = 0.5;  // one that ranks by its error wins over more efficient ones that do not
  EXPECT_EQ(firstshot::bestPilotFigure(f), 2u);
}

// A method with a fixed cost (the cache's fill) at the render's budget: the passes' noise shrinks with the rays the
// fill leaves them, the records' frozen error and the bias stay.
TEST(IntegratorPilot, AFixedCostIsChargedAtItsShareOfTheRender) {
  using firstshot::renderEfficiency;
  // No fixed cost, no frozen part: what the others get, 1 / (noise² · rays), at any render budget.
  EXPECT_NEAR(renderEfficiency(0.1, 0.0, 0.0, 1e5, 0.0, 1e6), 1.0 / (0.01 * 1e5), 1e-12);
  EXPECT_NEAR(renderEfficiency(0.1, 0.0, 0.0, 1e5, 0.0, 1e8), 1.0 / (0.01 * 1e5), 1e-12);
  // All of it frozen: more passes do not help, the render's rays are the work.
  EXPECT_NEAR(renderEfficiency(0.1, 0.1, 0.0, 1e5, 0.0, 1e6), 1.0 / (0.01 * 1e6), 1e-12);
  // A fill of half the render: its passes get half the rays, e² = 0.01 · 1e5 / 5e5.
  EXPECT_NEAR(renderEfficiency(0.1, 0.0, 0.0, 1e5, 5e5, 1e6), 1.0 / (0.01 * 0.2 * 1e6), 1e-12);
  // Bias adds in quadrature and stays: 0.03² + 0.04² at any number of passes.
  EXPECT_NEAR(renderEfficiency(0.03, 0.03, 0.04, 1e5, 0.0, 1e6), 1.0 / (0.0025 * 1e6), 1e-12);
  // A fill that takes the whole render leaves nothing to render with; so does no pass measured.
  EXPECT_EQ(renderEfficiency(0.1, 0.0, 0.0, 1e5, 1e6, 1e6), 0.0);
  EXPECT_EQ(renderEfficiency(0.1, 0.0, 0.0, 0.0, 0.0, 1e6), 0.0);
  // No error at all (the direct light of a point over a plane by NEE: two pictures alike) counts as 10⁻⁴: methods that
  // exact are equals, and the cheaper wins (an error of 0 made an efficiency of 0: the noisiest method won there).
  EXPECT_NEAR(renderEfficiency(0.0, 0.0, 0.0, 1e5, 0.0, 1e6), 1.0 / (1e-8 * 1e5), 1e-6);
  EXPECT_EQ(renderEfficiency(0.0, 0.0, 0.0, 1e5, 0.0, 1e6), renderEfficiency(5e-5, 0.0, 0.0, 1e5, 0.0, 1e6));
  EXPECT_GT(renderEfficiency(0.0, 0.0, 0.0, 1e5, 0.0, 1e6), renderEfficiency(0.0, 0.0, 0.0, 2e5, 0.0, 1e6));
  // The same fill at a larger render is worth more: the fixed cost amortised.
  EXPECT_GT(renderEfficiency(0.1, 0.0, 0.0, 1e5, 5e5, 1e7), renderEfficiency(0.1, 0.0, 0.0, 1e5, 5e5, 1e6));
}

// The render's records may gather with more hemisphere rays than the pilot's: their own noise² falls as 1/m, their
// fill grows m times (at most three quarters of the render's work), and the m of the best efficiency is taken. At 20 s the
// Cornell box, McGuire's, the window room and the textured room took 2-4x the rays, and their noise at 20 s fell 1.4-2x
// (docs/measurements.md, "The cache's records gathered to the budget").
TEST(IntegratorPilot, TheRendersRecordsTakeTheRaysItsBudgetPaysFor) {
  using firstshot::bestRecordSamples;
  using firstshot::renderEfficiency;
  double e = 0.0;
  // The records' own noise is most of the error and the fill 1% of the render: up to 16 times the rays.
  EXPECT_EQ(bestRecordSamples(0.1, 0.05, 0.0, 0.0, 1e5, 1e5, 1e7, e), 16);
  EXPECT_NEAR(e, renderEfficiency(std::sqrt(0.01 + 0.0025 / 16), std::sqrt(0.0025 / 16), 0.0, 1e5, 16e5, 1e7),
              1e-9 * e);
  // Without noise of their own (their placement's error alone) more rays buy nothing.
  EXPECT_EQ(bestRecordSamples(0.1, 0.0, 0.05, 0.0, 1e5, 1e5, 1e7, e), 1);
  // A bias that holds the error: the same.
  EXPECT_EQ(bestRecordSamples(0.1, 0.001, 0.0, 0.2, 1e5, 1e5, 1e7, e), 1);
  // A fill of 40% of the render: twice the rays would pass three quarters of it. With m = 1 the efficiency is
  // renderEfficiency's.
  EXPECT_EQ(bestRecordSamples(0.1, 0.05, 0.0, 0.0, 1e5, 4e6, 1e7, e), 1);
  EXPECT_EQ(e, renderEfficiency(std::sqrt(0.01 + 0.0025), 0.05, 0.0, 1e5, 4e6, 1e7));
  // At 30%, twice the rays (60%) pay where the records' own noise holds the error (Bitterli's box with its table:
  // 1024 rays per record, 48% of the time, 0.0073 against 0.0103 at 512).
  EXPECT_EQ(bestRecordSamples(0.01, 0.05, 0.0, 0.0, 1e5, 3e6, 1e7, e), 2);
  // The option given is the user's: the pilot's choice does not change it.
  for (const bool given : {false, true}) {
    CLI::App app;
    firstshot::IrradianceCacheCli cli;
    cli.add(app);
    app.parse(given ? "--ic-samples 256" : "", false);
    cli.setRecordSamples(2048);
    EXPECT_EQ(cli.recordSamples(), given ? 256 : 2048);
  }
}

// Under --time the records' fill at the pilot's choice of rays is projected in this machine's seconds (the pilot's
// fills' time, grown as their rays): where it would pass the three quarters of the time at which the fill stops
// (its later pixels then path traced), the records take half the rays, or a quarter, … down to a quarter of the
// pilot's, the largest count whose fill takes at most half the time.
TEST(IntegratorPilot, TheRecordsTakeFewerRaysWhereThisMachinesFillWouldBeStopped) {
  using firstshot::recordSamplesForTime;
  firstshot::PilotFigure f;
  f.recordSamples = 4;
  f.fillSeconds = 0.1;  // 0.4 s of fill at 4 times the pilot's rays
  EXPECT_EQ(recordSamplesForTime(f, 20.0), 4.0);
  EXPECT_EQ(recordSamplesForTime(f, 0.54), 4.0);  // 0.4 s within 0.75 x 0.54 s: it ends, however little is left
  EXPECT_EQ(recordSamplesForTime(f, 0.5), 2.0);   // 0.4 s past 0.375 s; at 2, 0.2 s: within half of 0.5 s
  EXPECT_EQ(recordSamplesForTime(f, 0.4), 2.0);
  EXPECT_EQ(recordSamplesForTime(f, 0.39), 1.0);  // at 2, 0.2 s: past half; at 1, 0.1 s
  EXPECT_EQ(recordSamplesForTime(f, 0.19), 0.5);
  EXPECT_EQ(recordSamplesForTime(f, 0.01), 0.25);  // none fits: a quarter of the pilot's rays
  f.recordSamples = 1;
  EXPECT_EQ(recordSamplesForTime(f, 0.14), 1.0);  // 0.1 s within 0.105 s
  EXPECT_EQ(recordSamplesForTime(f, 0.12), 0.5);
  EXPECT_EQ(recordSamplesForTime(f, 0.09), 0.25);
  // Not measured (not a seeded preprocessing) or no time given: the pilot's choice.
  f.fillSeconds = 0.0;
  EXPECT_EQ(recordSamplesForTime(f, 0.01), 1.0);
  f.fillSeconds = 0.1;
  EXPECT_EQ(recordSamplesForTime(f, 0.0), 1.0);
}
