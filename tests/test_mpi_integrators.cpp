// The integrators' rank-split preprocessing (common/comm.h), simulated by threads: with 2 and 3
// ranks every rank ends with exactly the state of one process, bit for bit.
// - Irradiance cache: the two-pass fill's records, every level, in order, with their radii.
// - Ray bundles: I_k, P_k and the outgoing radiance of every element side after each iteration.
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <mutex>

#include "common/error.h"
#include "common/interrupt.h"
#include "render/camera.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/irradiance_cache_util.h"
#include "tests/thread_comm.h"

namespace fs {
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

/// Every level's records of a two-pass fill of @p scene, as bytes; @p stats receives the counters.
std::string fillRecords(const RenderScene& scene, Comm* comm, IrradianceCacheStats* stats = nullptr) {
  IntegratorOptions io;
  io.comm = comm;
  IrradianceCacheIntegrator ic(io, smallCache());
  ic.preprocess(scene);
  std::string s;
  for (int l = 0; l < ic.cache().levels(); ++l) appendBytes(s, ic.cache().records(l));
  if (stats) *stats = ic.stats();
  return s;
}

// Cornell box (its area light gathered by the cache) at 32² pixels, no table: neighbour clamping
// and the second sweep make the merge order matter.
TEST(MpiIrradianceCache, FillIsTheSameForOneTwoAndThreeRanks) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 32;
  IrradianceCacheStats serialStats;
  std::string serial;
  {
    const RenderScene scene(desc);
    serial = fillRecords(scene, nullptr, &serialStats);
  }
  ASSERT_GT(serialStats.perLevel.size(), 1u);
  EXPECT_GT(serialStats.perLevel[0], 20u);
  EXPECT_GT(serialStats.perLevel[1], 0u);
  EXPECT_EQ(serialStats.exchangeBytes, 0u);
  expectSameOnEveryRank(serial, [&](Comm& comm) {
    const RenderScene scene(desc);
    IrradianceCacheStats st;
    std::string s = fillRecords(scene, &comm, &st);
    EXPECT_GT(st.exchangeBytes, 0u) << "rank " << comm.rank();
    EXPECT_EQ(st.fillRounds, serialStats.fillRounds);
    return s;
  });
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
      ic.preprocessRays(scene, 256, [&](size_t i, const std::function<Color(const Ray&, Sampler&)>& li) {
        if (i == 5) requestInterrupt(SIGINT);  // task 5: the third batch (tasks 3..6), rank 2's
        Sampler sampler(1, i, 0);
        li(camera.generateRay(float(i % 16) + 0.5f, float(i / 16) + 0.5f), sampler);
        ++traced;
      }, 0.01f);
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
  test::runRanks(2, [&](Comm& comm) {
    const RenderScene scene(desc);
    IntegratorOptions io;
    io.comm = &comm;
    IrradianceCacheSettings s = smallCache();
    s.twoPass = false;
    IrradianceCacheIntegrator ic(io, s);
    try {
      ic.preprocess(scene);
      ADD_FAILURE() << "one pass accepted on rank " << comm.rank();
    } catch (const InputError& e) {
      EXPECT_EQ(e.element(), "--one-pass");
    }
  });
  // One rank of one: accepted.
  test::runRanks(1, [&](Comm& comm) {
    const RenderScene scene(desc);
    IntegratorOptions io;
    io.comm = &comm;
    IrradianceCacheSettings s = smallCache();
    s.twoPass = false;
    IrradianceCacheIntegrator ic(io, s);
    EXPECT_NO_THROW(ic.preprocess(scene));
  });
}

}  // namespace
}  // namespace fs
