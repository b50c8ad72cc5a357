// Light tracing's emitters chosen by what the camera sees of their light (render/integrators/light/
// emitter_importance.h): a light in a closed room the camera is not in keeps its defensive share, the measurement
// is the same for any thread count, and the image is the power choice's, less noisy.
#include <gtest/gtest.h>

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <cstring>
#include <memory>

#include "render/integrators/common/emitter_importance.h"
#include "render/integrators/common/shooting_integrator.h"
#include "tests/block_compare.h"
#include "tests/hidden_lights_scenes.h"
#include "tests/light_tracing_util.h"

using namespace firstshot;

namespace {

/// The hidden-lights room lit by a 5 W point light, and beside it a closed room (its own walls, 3 m away) holding a
/// 50 W one: by power 10/11 of the particles would light a room the camera does not see.
SceneDesc twoRooms() {
  return test::hiddenLightsRoom(R"("other": {"type": "diffuse", "albedo": 0.7})",
                                R"({"type": "box", "material": "other", "min": [5,0,0], "max": [7,1.5,2], "flip_normals": true}],
                                   "lights": [{"type": "point", "position": [1, 1.3, 1], "power": 5},
                                              {"type": "point", "position": [6, 1, 1], "power": 50})");
}

std::unique_ptr<Integrator> shooting(const std::string& name, const RenderScene& scene, bool camera) {
  IntegratorOptions io;
  io.maxDepth = scene.desc().settings.maxDepth;
  io.cameraEmitterChoice = camera;
  auto i = makeIntegrator(name, io);
  i->preprocess(scene);
  return i;
}

const EmitterImportance& importance(const Integrator& i) {
  return dynamic_cast<const ShootingIntegrator&>(i).emitterImportance();
}

}  // namespace

// The other room's light: no particle of it reaches the camera, so its group measures 0 and keeps the defensive
// share of its power choice; the room's light takes the rest. The factors are the same on one and two threads.
TEST(LightEmitterChoice, LightInAnotherRoomKeepsItsDefensiveShare) {
  const SceneDesc d = twoRooms();
  std::vector<double> factors[2];
  for (int threads : {1, 2}) {
    tbb::global_control cap(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const RenderScene scene(d, d.settings.patchSize);  // its own memo: measured again
    const auto lt = shooting("light", scene, true);
    const EmitterImportance& m = importance(*lt);
    ASSERT_GE(m.groups.size(), 2u);
    const EmitterGroupMoment &room = m.groups[0], &other = m.groups[1];
    EXPECT_NEAR(room.choice, 1.0 / 11.0, 1e-6);
    EXPECT_NEAR(other.choice, 10.0 / 11.0, 1e-6);
    EXPECT_GT(other.particles, 0.8 * double(importanceParticles(2)));
    EXPECT_EQ(other.moment, 0.0);
    EXPECT_GT(room.moment, 0.0);
    EXPECT_DOUBLE_EQ(other.newChoice, kDefensiveShare * other.choice);
    EXPECT_NEAR(room.newChoice + other.newChoice, 1.0, 1e-6);  // the choices from float probabilities
    EXPECT_GT(m.gain, 4.0);
    fmt::print("{} thread(s): the room's light {:.3f} -> {:.3f} of the particles, projected gain {:.2f}\n", threads,
               room.choice, room.newChoice, m.gain);
    factors[threads - 1] = m.factor;
  }
  ASSERT_EQ(factors[0].size(), factors[1].size());
  EXPECT_EQ(std::memcmp(factors[0].data(), factors[1].data(), factors[0].size() * sizeof(double)), 0);
}

// The same image as the power choice's (every 8 × 8 block within 3σ; the two with other seeds), and its pixels'
// variance per pass lower by more than 4× (light tracing: the room's light gets 8× the particles;
// BDPT: its light subpaths, and its strategy s = 1, which chooses the lights as they do).
TEST(LightEmitterChoice, SameImageLessNoise) {
  FIRSTSHOT_STATISTICS_ONLY("LightEmitterChoice.LightInAnotherRoomKeepsItsDefensiveShare");
  const SceneDesc d = twoRooms();
  const RenderScene scene(d, d.settings.patchSize);
  for (const std::string name : {"light", "bdpt"}) {
    const auto camera = shooting(name, scene, true), power = shooting(name, scene, false);
    EXPECT_NEAR(importance(*camera).groups.at(1).newChoice, kDefensiveShare * 10.0 / 11.0, 1e-6) << name;
    const int passes = name == "light" ? 400 : 200;
    test::expectBlocksAgree(name + ", emitters by the camera against by power", test::blockMeans(*camera, scene, passes),
                            test::blockMeans(*power, scene, passes, 2));
    const test::Moments vc = test::pixelVariance(*camera, scene, 40), vp = test::pixelVariance(*power, scene, 40);
    fmt::print("{}, pixel variance per pass: by the camera {:.4g} ± {:.2g}, by power {:.4g} ± {:.2g} (ratio {:.2f})\n",
               name, vc.mean(), vc.se(), vp.mean(), vp.se(), vp.mean() / vc.mean());
    EXPECT_GT(vp.mean() - 3 * vp.se(), 4.0 * (vc.mean() + 3 * vc.se())) << name;
  }
}
