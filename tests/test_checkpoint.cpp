// Render checkpoints in-process (render/loop/checkpoint.h): for every integrator, a render stopped in
// the middle of a pass, saved, restored into a new film and resumed ends with the same sums, bit
// for bit, as an uninterrupted render; damaged, foreign and mismatched checkpoints are refused.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/formats/load_scene.h"
#include "common/util/error.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/loop/checkpoint.h"
#include "render/loop/splat_renderer.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

constexpr int kWidth = 32, kHeight = 24, kSpp = 4;

/// Forwards to @p inner (its interface @p Base) and raises @p flag after @p limit calls of Li() or
/// splatParticles(): the render then stops wherever it is, as after SIGINT.
template <class Base>
class CancelAfter : public Base {
 public:
  CancelAfter(const Base& inner, std::atomic<bool>& flag, uint64_t limit) : inner_(inner), flag_(flag), limit_(limit) {}
  void preprocess(const RenderScene&) override {}
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info) const override {
    count();
    return inner_.Li(ray, sampler, info);
  }
  std::string name() const override { return inner_.name(); }

 protected:
  void count() const {
    if (++calls_ > limit_) flag_ = true;
  }
  const Base& inner_;

 private:
  std::atomic<bool>& flag_;
  uint64_t limit_;
  mutable std::atomic<uint64_t> calls_{0};
};

class CancelSplatsAfter : public CancelAfter<SplattingIntegrator> {
 public:
  using CancelAfter::CancelAfter;
  uint64_t particlesPerPass(const Camera& camera) const override { return inner_.particlesPerPass(camera); }
  void splatParticles(const Camera& camera, uint64_t seed, uint64_t jitterSeed, SamplerMode mode, uint64_t pass,
                      uint64_t begin, uint64_t end, std::vector<Splat>& out, uint64_t& rays) const override {
    count();
    inner_.splatParticles(camera, seed, jitterSeed, mode, pass, begin, end, out, rays);
  }
};

class CancelPassesAfter : public CancelAfter<PassIntegrator> {
 public:
  using CancelAfter::CancelAfter;
  void beginPass(int sampleIndex, uint64_t seed) const override { inner_.beginPass(sampleIndex, seed); }
};

/// The CancelAfter of @p inner's kind.
std::unique_ptr<Integrator> cancelAfter(const Integrator& inner, std::atomic<bool>& flag, uint64_t limit) {
  switch (inner.kind()) {
    case IntegratorKind::Splatting:
      return std::make_unique<CancelSplatsAfter>(static_cast<const SplattingIntegrator&>(inner), flag, limit);
    case IntegratorKind::PerPass:
      return std::make_unique<CancelPassesAfter>(static_cast<const PassIntegrator&>(inner), flag, limit);
    case IntegratorKind::Sampling: break;
  }
  return std::make_unique<CancelAfter<Integrator>>(inner, flag, limit);
}

std::unique_ptr<Integrator> makePreprocessed(const std::string& name, const RenderScene& scene) {
  auto it = makeIntegrator(name, IntegratorOptions());
  if (auto* ic = dynamic_cast<IrradianceCacheIntegrator*>(it.get())) {
    IrradianceCacheSettings s;
    s.samples = 64, s.bounces = 1, s.twoPass = true;  // one-pass caches cannot resume exactly
    ic->setSettings(s);
  }
  it->preprocess(scene);
  return it;
}

RenderOptions options(int threads) {
  RenderOptions ro;
  ro.spp = kSpp;
  ro.seed = 3;
  ro.threads = threads;
  return ro;
}

void expectSameSums(const Film& a, const Film& b) {
  const Film::Sums &p = a.sums(), &q = b.sums();
  ASSERT_EQ(p.count, q.count);
  for (const auto& [u, v] : {std::pair{&p.sum, &q.sum}, std::pair{&p.sumSq, &q.sumSq}, std::pair{&p.albedo, &q.albedo},
                             std::pair{&p.normal, &q.normal}})
    ASSERT_EQ(std::memcmp(u->data(), v->data(), u->size() * sizeof(Vec3d)), 0);
}

const CheckpointKey kKey = {{"integrator", "test"}, {"seed", "3"}};

}  // namespace

class CheckpointResume : public ::testing::TestWithParam<std::string> {};

TEST_P(CheckpointResume, StoppedMidPassSavedRestoredAndResumedEqualsUninterrupted) {
  SceneDesc d = loadScene(test::source("scenes/cornell.json"));
  d.camera.width = kWidth, d.camera.height = kHeight;
  const RenderScene scene(d, 0.1);
  const Camera camera(d.camera);
  const auto reference = makePreprocessed(GetParam(), scene);
  Film full(kWidth, kHeight);
  render(*reference, camera, full, options(1));

  // Stopped after 1.5 passes' worth of camera samples (splatting: after pass 0's particle chunks,
  // so that pass 1 is dropped when its first particle chunk sees the flag).
  const auto inner = makePreprocessed(GetParam(), scene);
  std::atomic<bool> stop{false};
  const auto* splatting = dynamic_cast<const SplattingIntegrator*>(inner.get());
  const uint64_t limit = splatting ? (splatting->particlesPerPass(camera) + kSplatChunk - 1) / kSplatChunk
                                   : uint64_t(kWidth * kHeight) * 3 / 2;
  const auto cancelling = cancelAfter(*inner, stop, limit);
  Film partial(kWidth, kHeight);
  RenderOptions ro = options(2);
  ro.cancel = &stop;
  const RenderStats st = render(*cancelling, camera, partial, ro);
  EXPECT_TRUE(st.cancelled);
  const std::string file = test::tempDir() + "/a.checkpoint";
  writeCheckpoint(file, kKey, partial);

  // A new process would start from here: a fresh integrator and an empty film.
  const auto resumed = makePreprocessed(GetParam(), scene);
  Film film(kWidth, kHeight);
  const int passes = readCheckpoint(file, kKey, film);
  uint32_t most = 0;
  for (const uint32_t c : film.sums().count) most = std::max(most, c);
  if (splatting) {  // a splat pass is kept whole or dropped
    EXPECT_EQ(passes, 1);
    EXPECT_EQ(most, 1u);
  } else {  // stopped with some pixels further than others (tile by tile, or in the second pass)
    EXPECT_LT(passes, kSpp);
    EXPECT_GT(int(most), passes);
  }
  RenderOptions rest = options(2);
  rest.firstSample = passes, rest.spp = kSpp - passes, rest.skipTaken = true;
  render(*resumed, camera, film, rest);
  expectSameSums(full, film);
}

INSTANTIATE_TEST_SUITE_P(EveryIntegrator, CheckpointResume, ::testing::ValuesIn(integratorNames()),
                         [](const auto& p) {
                           std::string n = p.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

TEST(CheckpointFile, RefusesMissingDamagedAndMismatchedFiles) {
  Film film(4, 3);
  film.add(1, 2, Color(0.5f, 1.0f, 2.0f), Color(0.3f), Vec3(0.0f, 0.0f, 1.0f));
  const std::string dir = test::tempDir(), file = dir + "/c.checkpoint";
  writeCheckpoint(file, kKey, film);
  Film back(4, 3);
  EXPECT_EQ(readCheckpoint(file, kKey, back), 0);  // pixel (1, 2) holds one sample, the others none
  expectSameSums(film, back);

  auto refused = [&](const std::string& path, const CheckpointKey& key, int w, int h) {
    Film f(w, h);
    try {
      readCheckpoint(path, key, f);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return std::string(e.what());
    }
    ADD_FAILURE() << "accepted " << path;
    return std::string();
  };
  EXPECT_THAT(refused(dir + "/none.checkpoint", kKey, 4, 3), HasSubstr("cannot open"));
  EXPECT_THAT(refused(file, {{"integrator", "test"}, {"seed", "4"}}, 4, 3),
              HasSubstr("seed is \"3\" in the checkpoint but \"4\" now"));
  EXPECT_THAT(refused(file, {{"integrator", "test"}}, 4, 3), HasSubstr("seed is \"3\" in the checkpoint but not set now"));
  EXPECT_THAT(refused(file, kKey, 5, 3), HasSubstr("4x3"));

  const std::string bytes = test::readFile(file);
  test::writeText(dir + "/cut.checkpoint", bytes.substr(0, bytes.size() / 2));
  EXPECT_THAT(refused(dir + "/cut.checkpoint", kKey, 4, 3), HasSubstr("truncated"));
  std::string flipped = bytes;
  flipped[flipped.size() / 2] ^= 1;
  test::writeText(dir + "/flipped.checkpoint", flipped);
  EXPECT_THAT(refused(dir + "/flipped.checkpoint", kKey, 4, 3), HasSubstr("checksum"));
  test::writeText(dir + "/other.checkpoint", "FSICACHE" + bytes.substr(8));
  EXPECT_THAT(refused(dir + "/other.checkpoint", kKey, 4, 3), HasSubstr("not a firstshot-render checkpoint"));
}

TEST(CheckpointFile, ContentHashFollowsTheBytes) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/a.txt", "abc");
  test::writeText(dir + "/b.txt", "abd");
  EXPECT_NE(fileContentHash(dir + "/a.txt"), fileContentHash(dir + "/b.txt"));
  EXPECT_EQ(fileContentHash(dir + "/a.txt"), fileContentHash(dir + "/a.txt"));
  EXPECT_EQ(fileContentHash(dir + "/missing.txt"), "none");
  EXPECT_EQ(fileContentHash(""), "none");
}
