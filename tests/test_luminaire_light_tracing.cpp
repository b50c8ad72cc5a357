// Luminaires in light tracing (render/integrators/light/integrator.h): particles leave the exit patches with the
// exit distribution, and the luminaires' own lights' particles end where they leave the box. The exit particles must
// carry the luminaires' exit power, each the same power up to its bin's colour, and the inner particles stay in their
// box (the images: test_luminaire_render.cpp). The per-sample noise with and without the luminaires is printed.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <tbb/global_control.h>

#include <atomic>
#include <cmath>
#include <utility>

#include "render/integrators/common/luminaire_split.h"
#include "render/integrators/light/integrator.h"
#include "tests/block_compare.h"
#include "tests/hidden_lights_scenes.h"
#include "tests/light_tracing_util.h"

using namespace firstshot;

namespace {

/// Max depth 32 for both integrators: the exit distribution holds every bounce inside the box, which a shorter
/// path would cut (test_luminaire_render.cpp). With @p luminaires every luminaire is split (what these tests check),
/// not only where the split pays.
IntegratorOptions options(bool luminaires) {
  IntegratorOptions io;
  io.maxDepth = 32;
  io.luminaires = luminaires;
  io.splitEveryLuminaire = luminaires;
  return io;
}

/// The mean pixel variance of one pass of light tracing with and without the luminaires on @p scene, printed.
void printNoise(const std::string& name, const RenderScene& scene, int pairs) {
  auto on = makeIntegrator("light", options(true)), off = makeIntegrator("light", options(false));
  on->preprocess(scene);
  off->preprocess(scene);
  const test::Moments von = test::pixelVariance(*on, scene, pairs), voff = test::pixelVariance(*off, scene, pairs);
  fmt::print("{}, light tracing, mean pixel variance per pass: luminaires {:.4g} ± {:.2g}, lights as lights "
             "{:.4g} ± {:.2g} (ratio {:.2f})\n", name, von.mean(), von.se(), voff.mean(), voff.se(),
             voff.mean() / von.mean());
  EXPECT_GT(von.mean(), 0.0);
  EXPECT_GT(voff.mean(), 0.0);
}

}  // namespace

// The emitters' particles, drawn as light tracing draws them: those of the exit patches carry Σ exitPower and those
// of the luminaires' lights Σ power (each within 3σ per channel, whatever share of the count they get); every exit
// particle's power is P·L_b/mean(L_b) (P the emitters' total choice weight, mean RGB: exit_emission.h), so its mean
// RGB is P; its direction's density is pdfDirection's.
TEST(LuminaireLightTracing, ExitParticlesCarryTheExitPower) {
  for (const auto& [name, d] : {std::pair{"bowl lamp", test::bowlLamp()}, std::pair{"glass bulb", test::glassBulb()},
                                std::pair{"open box", test::openBox()}}) {
    const RenderScene scene = test::withLuminaireTable(d);
    const FirstShotTable& table = *scene.firstShot();
    ASSERT_FALSE(table.luminaires.empty()) << name;
    LightTracingIntegrator lt(options(true));
    lt.preprocess(scene);
    ASSERT_TRUE(lt.usesLuminaires());
    const EmissionSampler& em = lt.particleEmitters();
    ASSERT_EQ(em.exits().count(), scene.luminaires().exitCount());
    Color exitPower(0.0f), lightPower(0.0f);
    for (const Luminaire& lum : table.luminaires) exitPower += lum.exitPower, lightPower += lum.power;
    const uint64_t n = 200000;
    test::Moments exits[3], inner[3];
    int exitParticles = 0, badPower = 0, badPdf = 0;
    for (uint64_t i = 0; i < n; ++i) {
      Sampler sampler(3, i, 0, LightTracingIntegrator::kParticleStream);
      EmissionSample es;
      Color pe(0.0f), pl(0.0f);
      if (em.sample(sampler, es, i, n)) {
        if (em.isExit(es.light)) {
          pe = es.power, ++exitParticles;
          if (std::abs(test::gray(es.power) / em.totalPower() - 1.0) > 1e-4) ++badPower;
          const float pdf = em.pdfDirection(es.light, es.p, es.n, es.d);
          if (std::abs(pdf / es.pdfDir - 1.0f) > 1e-3f) ++badPdf;  // a direction on a bin's border may round over
        } else if (scene.luminaires().ofLight(es.light) >= 0) {
          pl = es.power;
        }
      }
      for (int c = 0; c < 3; ++c) exits[c].add(pe[c]), inner[c].add(pl[c]);
    }
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(exits[c].mean(), exitPower[c], 3.0 * exits[c].se() + 1e-6 * exitPower[c]) << name << " channel " << c;
      EXPECT_NEAR(inner[c].mean(), lightPower[c], 3.0 * inner[c].se() + 1e-6 * lightPower[c]) << name << " channel " << c;
    }
    if (test::gray(exitPower) > 0.0) EXPECT_GT(exitParticles, 1000) << name;
    else EXPECT_EQ(exitParticles, 0) << name << ": all its light leaves through glass (the specular light)";
    EXPECT_EQ(badPower, 0) << name;
    EXPECT_LE(badPdf, exitParticles / 1000) << name;
    fmt::print("{}: exit power {:.4f} W (table {:.4f} W), {} of {} particles from the exit patches\n", name,
               test::gray(Color(float(exits[0].mean()), float(exits[1].mean()), float(exits[2].mean()))),
               test::gray(exitPower), exitParticles, n);
  }
}

// A luminaire's light's particle ends where it leaves the box after a bounce off a non-delta surface inside it: no
// vertex of it lies outside past a non-delta vertex inside. One that leaves straight from the light (the direct light)
// or after delta bounces only (through glass: the specular light), neither in the exit distribution, goes on into the
// room. Exit particles go on bouncing in the room.
TEST(LuminaireLightTracing, InnerParticlesStayInTheirBox) {
  for (const bool glass : {false, true}) {
    const RenderScene scene = test::withLuminaireTable(glass ? test::glassBulb() : test::bowlLamp());
    LightTracingIntegrator lt(options(true));
    lt.preprocess(scene);
    const EmissionSampler& em = lt.particleEmitters();
    const LuminaireBoxes& boxes = scene.luminaires();
    std::atomic<int> outsideAfterScattering{0}, inner{0}, direct{0}, specular{0}, exitPaths{0}, longExit{0};
    test::forEachLightPath(scene, lt, 20000, 5, [&](uint64_t, const std::vector<LightVertex>& path) {
      if (path.empty()) return;
      const uint32_t e = path[0].light;
      if (em.isExit(e)) {
        ++exitPaths;
        if (path.size() > 2) ++longExit;
        return;
      }
      const int lum = boxes.ofLight(e);
      if (lum < 0) return;
      ++inner;
      const Luminaire& box = boxes.items()[size_t(lum)];
      bool scattered = false;
      for (size_t k = 1; k < path.size(); ++k) {
        if (!box.contains(path[k].hit.p)) {
          if (scattered) ++outsideAfterScattering;
          else ++(k == 1 ? direct : specular);
          return;
        }
        scattered = scattered || !path[k].delta;
      }
    });
    const char* name = glass ? "glass bulb" : "bowl lamp";
    EXPECT_EQ(outsideAfterScattering.load(), 0) << name;
    EXPECT_GT(inner.load(), 100) << name;
    if (glass) {
      EXPECT_EQ(direct.load(), 0) << "nothing leaves the glass bulb but through the glass";
      EXPECT_GT(specular.load(), inner.load() / 2) << "the filament's light through the glass";
    } else {
      EXPECT_GT(direct.load(), 10) << "the bulb's direct light through the bowl's opening";
      EXPECT_LT(direct.load(), inner.load());
      EXPECT_GT(exitPaths.load(), 100);
      EXPECT_GT(longExit.load(), 10);
    }
  }
}

// Where light tracing and BDPT split a luminaire's light (luminaire_split.h): each split as the measured parts say,
// (√A + √(f·B))² < A + B, the lights' share in [kMinInnerShare, 1]; the same parts for one thread and two; and where
// the camera looks into the open box (its inside the lights' part), at the filament's glass (no exit part) or past the
// box at the wall its point light lights straight through the opening, nothing is split; with a spot light aimed at
// the box's back wall instead (no light straight out, the inside hidden) it is.
TEST(LuminaireLightTracing, SplitWhereItPays) {
  struct Case {
    const char* name;
    SceneDesc d;
    int split;  // expected: 1 split, 0 not
  };
  const SceneDesc away = test::openBox(false, true);  // the camera beside the box, looking past it
  SceneDesc spot = test::openBox();
  spot.camera = away.camera;
  spot.lights[0].type = LightType::Spot;
  spot.lights[0].direction = Vec3d(0, 0, -1);  // at the back wall 0.1 m away, within its 15 cm
  for (const Case& c : {Case{"open box", test::openBox(), 0}, Case{"glass bulb", test::glassBulb(), 0},
                        Case{"open box from beside", away, 0}, Case{"spot in the open box from beside", spot, 1}}) {
    const RenderScene scene = test::withLuminaireTable(c.d);
    LightTracingIntegrator lt(options(false));
    lt.preprocess(scene);
    uint64_t rays = 0;
    std::vector<LuminaireSplit> one, two;
    {
      tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
      one = measureLuminaireSplits(scene, lt.particleEmitters(), 32, rays);
    }
    {
      tbb::global_control g(tbb::global_control::max_allowed_parallelism, 2);
      two = measureLuminaireSplits(scene, lt.particleEmitters(), 32, rays);
    }
    ASSERT_EQ(one.size(), scene.luminaires().items().size()) << c.name;
    for (size_t i = 0; i < one.size(); ++i) {
      const Luminaire& lum = scene.luminaires().items()[i];
      const double f = test::gray(lum.exitPower) / test::gray(lum.power);
      const LuminaireSplit& s = one[i];
      EXPECT_EQ(s.inner, two[i].inner) << c.name;
      EXPECT_EQ(s.exit, two[i].exit) << c.name;
      const double a = std::sqrt(s.inner), b = std::sqrt(f * s.exit);
      EXPECT_EQ(s.split, s.exit > 0 && (a + b) * (a + b) < s.inner + s.exit) << c.name;
      if (s.split) {
        EXPECT_GE(s.innerShare, EmissionSampler::kMinInnerShare) << c.name;
        EXPECT_LE(s.innerShare, 1.0) << c.name;
      }
      fmt::print("{}: f {:.3f}, inner part {:.4g}, exit part {:.4g}: {}, lights' share {:.3f}\n", c.name, f, s.inner,
                 s.exit, s.split ? "split" : "not split", s.innerShare);
    }
    ASSERT_EQ(one.size(), 1u) << c.name;
    EXPECT_EQ(int(one[0].split), c.split) << c.name;
  }
}

// The images of light tracing with the luminaires against light tracing or path tracing without: in
// test_luminaire_render.cpp, beside the path tracer's.

// The per-sample noise with and without the luminaires (reported, not asserted: the particles that light the room
// leave the exit patches with the same power each instead of bouncing out of the fixture, while a share of the count
// goes to the inside of the boxes; on the glass bulb the path-traced pixels of the glass dominate).
TEST(LuminaireLightTracing, NoiseWithAndWithoutLuminaires) {
  printNoise("bowl lamp", test::withLuminaireTable(test::bowlLamp()), 30);
  printNoise("glass bulb", test::withLuminaireTable(test::glassBulb()), 30);
}
