// The integrators' rank-split preprocessing (common/util/comm.h), simulated by threads: with 2 and 3
// ranks every rank ends with exactly the state of one process, bit for bit.
// - Irradiance cache: the two-pass fill's records, every level, in order, with their radii.
// - Ray bundles: I_k, P_k, D_k and the outgoing radiance of every element side after each
//   iteration, and the rays counted.
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <mutex>

#include "common/formats/load_scene.h"
#include "common/util/error.h"
#include "common/util/interrupt.h"
#include "render/integrators/bundle/integrator.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/scene/camera.h"
#include "tests/irradiance_cache_util.h"
#include "tests/thread_comm.h"

namespace firstshot {
namespace {

/// The raw bytes of @p values (exact comparison, NaN payloads and signed zeros included).
template <class T>
void appendBytes(std::string& out, const std::vector<T>& values) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(std::to_string(values.size())).push_back(':');
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

/// Runs @p body on 2 and 3 simulated ranks and checks that every rank's state (what @p body
/// returns) equals @p serial; @p body also receives the rank's Comm.
void expectSameOnEveryRank(const std::string& serial, const std::function<std::string(Comm&)>& body) {
  for (int ranks : {2, 3}) {
    std::vector<std::string> states(static_cast<size_t>(ranks));
    test::runRanks(ranks, [&](Comm& comm) {
      std::string s = body(comm);
      static std::mutex m;
      std::lock_guard lock(m);
      states[size_t(comm.rank())] = std::move(s);
    });
    for (int r = 0; r < ranks; ++r) EXPECT_TRUE(states[size_t(r)] == serial) << ranks << " ranks, rank " << r;
  }
}

// ---- Irradiance cache ------------------------------------------------------------------------

IrradianceCacheSettings smallCache() {
  IrradianceCacheSettings s;
  s.samples = 64;
  s.bounces = 2;
  s.accuracy = 0.3f;
  s.threads = 1;
  return s;
}

/// Camera rays of @p camera's pixels as fill tasks (as sensors' preprocessRays() tasks).
RayTask cameraTasks(const Camera& camera) {
  return [&camera](size_t i, const std::function<Color(const Ray&, Sampler&)>& li) {
    const int w = camera.width();
    for (uint64_t k = 0; k < 2; ++k) {
      Sampler sampler(3, i, k);
      const Vec2 j = sampler.next2D();
      li(camera.generateRay(float(i % size_t(w)) + j.x, float(i / size_t(w)) + j.y), sampler);
    }
  };
}

/// Every level's records of a two-pass fill of @p scene (preprocess(), or with @p rays
/// preprocessRays() over the camera's pixels), as bytes; @p stats receives the counters.
std::string fillRecords(const RenderScene& scene, Comm* comm, IrradianceCacheStats* stats = nullptr, bool rays = false) {
  IntegratorOptions io;
  io.comm = comm;
  IrradianceCacheIntegrator ic(io, smallCache());
  const Camera camera(scene.desc().camera);
  if (rays)
    ic.preprocessRays(scene, size_t(camera.width()) * size_t(camera.height()), cameraTasks(camera), 0.02f);
  else
    ic.preprocess(scene);
  std::string s;
  for (int l = 0; l < ic.cache().levels(); ++l) appendBytes(s, ic.cache().records(l));
  if (stats) *stats = ic.stats();
  return s;
}

// Cornell box (its area light gathered by the cache) at 32² pixels, no table: neighbour clamping
// and the second sweep make the merge order matter. The camera's fill (preprocess) and a fill from
// rays (preprocessRays, as at sensors: misses over the task budget take paths).
TEST(MpiIrradianceCache, FillIsTheSameForOneTwoAndThreeRanks) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 32;
  for (bool rays : {false, true}) {
    SCOPED_TRACE(rays ? "preprocessRays" : "preprocess");
    IrradianceCacheStats serialStats;
    std::string serial;
    {
      const RenderScene scene(desc);
      serial = fillRecords(scene, nullptr, &serialStats, rays);
    }
    ASSERT_GT(serialStats.perLevel.size(), 1u);
    EXPECT_GT(serialStats.perLevel[0], 20u);
    EXPECT_GT(serialStats.perLevel[1], 0u);
    EXPECT_EQ(serialStats.exchangeBytes, 0u);
    fmt::print("{}: {} and {} records at levels 0 and 1\n", rays ? "preprocessRays" : "preprocess", serialStats.perLevel[0],
               serialStats.perLevel[1]);
    expectSameOnEveryRank(serial, [&](Comm& comm) {
      const RenderScene scene(desc);
      IrradianceCacheStats st;
      std::string s = fillRecords(scene, &comm, &st, rays);
      EXPECT_GT(st.exchangeBytes, 0u) << "rank " << comm.rank();
      EXPECT_EQ(st.fillRounds, serialStats.fillRounds);
      fmt::print("  {} ranks, rank {}: sent {} bytes, {:.3f} s in exchanges\n", comm.size(), comm.rank(), st.exchangeBytes,
                 st.exchangeSeconds);
      return s;
    });
  }
}

// SIGINT in the middle of a fill task of rank 2 (a record's gather() stops it): every rank stops at
// the same exchange with Interrupted, none waits forever.
TEST(MpiIrradianceCache, InterruptStopsEveryRank) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 16;
  const Camera camera(desc.camera);
  std::atomic<int> stopped{0}, traced{0};
  test::runRanks(3, [&](Comm& comm) {
    const RenderScene scene(desc);
    IntegratorOptions io;
    io.comm = &comm;
    IrradianceCacheIntegrator ic(io, smallCache());
    try {
      const RayTask pixels = cameraTasks(camera);
      ic.preprocessRays(scene, 256, [&](size_t i, const std::function<Color(const Ray&, Sampler&)>& li) {
        if (i == 5) requestInterrupt(SIGINT);  // task 5: the third batch (tasks 3..6), rank 2's
        pixels(i, li);
        ++traced;
      }, 0.02f);
    } catch (const Interrupted& e) {
      EXPECT_EQ(e.signal(), SIGINT);
      ++stopped;
    }
  });
  clearInterrupt();
  EXPECT_EQ(stopped.load(), 3);
  EXPECT_GE(traced.load(), 3);  // the first two batches finished
  EXPECT_LT(traced.load(), 7);
}

TEST(MpiIrradianceCache, OnePassIsRefusedWithSeveralRanks) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 8;
  for (const int ranks : {2, 1}) {  // refused with several ranks; one rank of one is accepted
    test::runRanks(ranks, [&](Comm& comm) {
      const RenderScene scene(desc);
      IntegratorOptions io;
      io.comm = &comm;
      IrradianceCacheSettings s = smallCache();
      s.twoPass = false;
      IrradianceCacheIntegrator ic(io, s);
      try {
        ic.preprocess(scene);
        EXPECT_EQ(ranks, 1) << "one pass accepted on rank " << comm.rank();
      } catch (const InputError& e) {
        EXPECT_EQ(ranks, 2);
        EXPECT_EQ(e.element(), "--one-pass");
      }
    });
  }
}

// ---- Ray bundles ------------------------------------------------------------------------------

/// The Cornell box with its area light, plus a point light (P_k) and a directional light falling on
/// the box from above (D_k, on the outside of the ceiling), at 16² pixels.
SceneDesc bundleScene() {
  SceneDesc desc = test::cornellWithPointLight(16);
  const SceneDesc original = loadScene(test::source("scenes/cornell.json"));
  desc.materials = original.materials;  // the area light emits again
  desc.lights = original.lights;
  desc.lights.push_back(test::cornellWithPointLight(16).lights[0]);
  LightDesc sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(Vec3d(0.3, -1.0, 0.2));
  sun.irradiance = Color(2.0f);
  desc.lights.push_back(sun);
  return desc;
}

/// I_k, P_k, D_k and the outgoing radiance of every element side after each of 4 iterations, and
/// the rays, as bytes; @p stats receives the exchange counters.
std::string bundleStates(const RenderScene& scene, Comm* comm, uint64_t* rays = nullptr, uint64_t* sent = nullptr) {
  IntegratorOptions io;
  io.comm = comm;
  BundleIntegrator b(io);
  BundleSettings settings;
  settings.resolution = 48;
  b.setSettings(settings);
  b.preprocess(scene);
  std::string s;
  for (int k = 0; k < 4; ++k) {
    b.beginPass(k, 7);
    const BundleTransfer& t = b.transfer();
    std::vector<Color> in, point, out, dir;
    for (uint32_t e = 0; e < t.elements().size(); ++e)
      for (int side = 0; side < 2; ++side) {
        in.push_back(t.incoming(e, side));
        point.push_back(t.incomingPoint(e, side));
        out.push_back(t.outgoing(e, side));
      }
    for (size_t d = 0; d < t.directionalLights().size(); ++d)
      for (uint32_t e = 0; e < t.elements().size(); ++e) dir.push_back(t.directionalIrradiance(d, e));
    for (const auto* v : {&in, &point, &out, &dir}) appendBytes(s, *v);
    s += std::to_string(t.lastRays()) + ";";
    if (rays) *rays += t.lastRays();
  }
  if (sent) *sent = b.transfer().exchangeBytes();
  return s;
}

TEST(MpiBundle, IterationsAreTheSameForOneTwoAndThreeRanks) {
  const SceneDesc desc = bundleScene();
  uint64_t rays = 0, sent = 0;
  std::string serial;
  {
    const RenderScene scene(desc);
    serial = bundleStates(scene, nullptr, &rays, &sent);
    // The states are not trivially equal: every kind of light reached some element.
    IntegratorOptions io;
    BundleIntegrator b(io);
    b.preprocess(scene);
    b.beginPass(1, 7);
    double in = 0, point = 0, dir = 0;
    for (uint32_t e = 0; e < b.transfer().elements().size(); ++e) {
      in += double(maxComponent(b.transfer().incoming(e, 0) + b.transfer().incoming(e, 1)));
      point += double(maxComponent(b.transfer().incomingPoint(e, 0) + b.transfer().incomingPoint(e, 1)));
      dir += double(maxComponent(b.transfer().directionalIrradiance(0, e)));
    }
    EXPECT_GT(in, 0.0);
    EXPECT_GT(point, 0.0);
    EXPECT_GT(dir, 0.0);
  }
  EXPECT_GT(rays, 4u * 48u * 48u);
  EXPECT_EQ(sent, 0u);
  expectSameOnEveryRank(serial, [&](Comm& comm) {
    const RenderScene scene(desc);
    uint64_t rankSent = 0;
    std::string s = bundleStates(scene, &comm, nullptr, &rankSent);
    EXPECT_GT(rankSent, 0u) << "rank " << comm.rank();
    fmt::print("  {} ranks, rank {}: sent {} bytes\n", comm.size(), comm.rank(), rankSent);
    return s;
  });
}

// A signal before a pass: no rank starts the iteration (each would wait for the others forever).
TEST(MpiBundle, InterruptStopsEveryRankBeforeTheIteration) {
  const SceneDesc desc = bundleScene();
  std::atomic<int> idle{0};
  requestInterrupt(SIGTERM);
  test::runRanks(2, [&](Comm& comm) {
    const RenderScene scene(desc);
    IntegratorOptions io;
    io.comm = &comm;
    BundleIntegrator b(io);
    b.preprocess(scene);
    b.beginPass(3, 7);
    if (b.transfer().iterations() == 0) ++idle;
  });
  clearInterrupt();
  EXPECT_EQ(idle.load(), 2);
}

}  // namespace
}  // namespace firstshot
