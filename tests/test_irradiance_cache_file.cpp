// The irradiance cache around the render: the two-pass image does not depend on the thread
// count; a cache file gives the same image with no new records; a corrupt, truncated, foreign or
// mismatched file is refused with a message naming it (exit code 2 from the tool); the shared
// one-pass cache works from two threads; footprint and neighbour clamping do what they promise;
// --show-records marks the record positions.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/util/error.h"
#include "render/integrators/irradiance_cache/cache_file.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/irradiance_cache_util.h"

using namespace firstshot;

namespace {

constexpr int kSize = 32;

struct Rendered {
  Film film{kSize, kSize};
  IrradianceCacheStats stats;
  std::vector<IrradianceRecord> level0;
};

// The cache settings stay written out per test (test_irradiance_cache_render.cpp too): their values differ.
IrradianceCacheSettings twoPass(const std::string& cacheFile = "", int threads = 0) {
  IrradianceCacheSettings s;
  s.accuracy = 0.2f;
  s.samples = 128;
  s.bounces = 2;
  s.footprintMin = 0.5f;
  s.twoPass = true;
  s.cacheFile = cacheFile;
  s.threads = threads;
  return s;
}

Rendered renderWith(const RenderScene& scene, const IrradianceCacheSettings& s, int threads = 0, int spp = 2,
                    double fillSeconds = 0.0) {
  IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
  ic.limitPreprocessSeconds(fillSeconds);
  ic.preprocess(scene);
  Rendered r;
  RenderOptions ro;
  ro.spp = spp;
  ro.seed = s.seed;
  ro.threads = threads;
  render(ic, Camera(scene.desc().camera), r.film, ro);
  if (!s.cacheFile.empty()) ic.saveCache(s.cacheFile);
  r.stats = ic.stats();
  r.level0 = ic.cache().records(0);
  return r;
}

bool sameImage(const Film& a, const Film& b) {
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      if (a.mean(x, y) != b.mean(x, y)) return false;
  return true;
}

std::vector<char> readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

/// Runs @p f, expecting an InputError whose message names @p path and contains @p what.
template <typename F>
void expectRefused(F&& f, const std::string& path, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no error; expected: " << what;
  } catch (const InputError& e) {
    fmt::print("  refused: {}\n", e.what());
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(IrradianceCacheTwoPass, ImageDoesNotDependOnTheThreadCount) {
  const RenderScene scene(test::cornellWithPointLight(kSize));
  const Rendered one = renderWith(scene, twoPass("", 1), 1), two = renderWith(scene, twoPass("", 2), 2);
  fmt::print("{} records ({} at level 0), {} private in the render\n", one.stats.records, one.level0.size(),
             one.stats.privateRecords);
  EXPECT_GT(one.stats.records, 0u);
  EXPECT_EQ(one.stats.records, two.stats.records);
  EXPECT_EQ(one.stats.privateRecords, two.stats.privateRecords);
  EXPECT_EQ(one.stats.missPaths, two.stats.missPaths);
  ASSERT_EQ(one.level0.size(), two.level0.size());
  for (size_t i = 0; i < one.level0.size(); ++i) {
    EXPECT_EQ(one.level0[i].p, two.level0[i].p);
    EXPECT_EQ(one.level0[i].E, two.level0[i].E);
    EXPECT_EQ(one.level0[i].R, two.level0[i].R);
  }
  EXPECT_TRUE(sameImage(one.film, two.film));
}

// A render sample that no record covers (the fill traced each pixel's first sample only) takes one path from there;
// with missRecords (--ic-miss record) it makes a record for itself, as Ward's method would. Both estimate the same
// image: the pixels' differences (zero where no sample missed) average to 0 within 4σ of their own spread.
TEST(IrradianceCacheTwoPass, AMissTakesAPathOrWithRecordMissMakesAPrivateRecord) {
  const RenderScene scene(test::cornellWithPointLight(kSize));
  IrradianceCacheSettings s = twoPass("", 2);
  const Rendered paths = renderWith(scene, s, 2, 8);
  s.missRecords = true;
  const Rendered records = renderWith(scene, s, 2, 8);
  fmt::print("8 spp: {} misses took a path; with record misses {} private records, {} paths\n", paths.stats.missPaths,
             records.stats.privateRecords, records.stats.missPaths);
  EXPECT_GT(paths.stats.missPaths, 0u) << "no sample missed: the test shows nothing";
  EXPECT_EQ(paths.stats.privateRecords, 0u);
  EXPECT_GT(records.stats.privateRecords, 0u);
  EXPECT_EQ(records.stats.missPaths, 0u);
  double sum = 0, sum2 = 0, mean = 0;
  const double n = 3.0 * kSize * kSize;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = paths.film.mean(x, y)[c] - records.film.mean(x, y)[c];
        sum += d, sum2 += d * d, mean += records.film.mean(x, y)[c] / n;
      }
  const double md = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - md * md) / n);
  fmt::print("mean difference {:+.3g} ± {:.3g} (image mean {:.4g})\n", md, sd, mean);
  EXPECT_GT(sd, 0.0) << "the images are the same: no miss changed a pixel";
  EXPECT_LT(std::abs(md), 4.0 * sd);
}

// A fill stopped by the time a render was given (limitPreprocessSeconds: --time, half of it) keeps what it made, and the
// samples its records do not cover take a path: the image estimates the same as after the whole fill. A limit of a
// nanosecond stops it after its first batch (one pixel, whose records an earlier one would cover: none kept, so every
// sample takes a path) on any machine; IntegratorAuto.TheCacheNamedSizesItsRaysToTheTimeGiven stops one in its
// middle. The pixels' differences average to 0 within 4σ of their own spread.
TEST(IrradianceCacheTwoPass, AFillStoppedByTheTimeStillEstimatesTheImage) {
  const RenderScene scene(test::cornellWithPointLight(kSize));
  const Rendered whole = renderWith(scene, twoPass("", 2), 2, 8), cut = renderWith(scene, twoPass("", 2), 2, 8, 1e-9);
  fmt::print("whole fill: {} records, {} misses took a path; stopped after {} of {} pixels: {} records, {} paths\n",
             whole.stats.records, whole.stats.missPaths, cut.stats.fillCutAt, cut.stats.fillPixels, cut.stats.records,
             cut.stats.missPaths);
  EXPECT_EQ(whole.stats.fillCutAt, 0u);
  EXPECT_EQ(cut.stats.fillCutAt, 1u);
  EXPECT_EQ(cut.stats.fillRounds, 1);
  EXPECT_LT(cut.stats.records, whole.stats.records);
  EXPECT_GT(cut.stats.missPaths, whole.stats.missPaths);
  double sum = 0, sum2 = 0;
  const double n = 3.0 * kSize * kSize;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = cut.film.mean(x, y)[c] - whole.film.mean(x, y)[c];
        sum += d, sum2 += d * d;
      }
  const double md = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - md * md) / n);
  fmt::print("mean difference {:+.3g} ± {:.3g}\n", md, sd);
  EXPECT_GT(sd, 0.0);
  EXPECT_LT(std::abs(md), 4.0 * sd);
}

TEST(IrradianceCacheFile, ReuseGivesTheSameImageWithNoNewRecords) {
  const RenderScene scene(test::cornellWithPointLight(kSize));
  const std::string file = test::tempDir() + "/cornell.fsic";
  const Rendered first = renderWith(scene, twoPass(file));
  ASSERT_TRUE(std::filesystem::exists(file));
  EXPECT_EQ(first.stats.loaded, 0u);
  const std::vector<char> bytes = readBytes(file);
  // Again from the file, on one thread.
  const Rendered second = renderWith(scene, twoPass(file, 1), 1);
  fmt::print("first run: {} records; second: {} loaded, {} in the end\n", first.stats.records, second.stats.loaded,
             second.stats.records);
  EXPECT_EQ(second.stats.loaded, first.stats.records);
  EXPECT_EQ(second.stats.records, second.stats.loaded) << "no new records";
  EXPECT_EQ(second.stats.privateRecords, first.stats.privateRecords);
  EXPECT_TRUE(sameImage(first.film, second.film));
  EXPECT_EQ(readBytes(file), bytes) << "rewritten identically";

  // One-pass from the same file: the loaded records serve the render.
  IrradianceCacheSettings s = twoPass(file);
  s.twoPass = false;
  const Rendered third = renderWith(scene, s);
  fmt::print("one pass from the file: {} loaded, {} in the end\n", third.stats.loaded, third.stats.records);
  EXPECT_LT(third.stats.records - third.stats.loaded, third.stats.loaded / 4);
}

TEST(IrradianceCacheFile, RefusesCorruptTruncatedForeignAndMismatchedFiles) {
  const SceneDesc desc = test::cornellWithPointLight(kSize);
  const RenderScene scene(desc);
  const std::string dir = test::tempDir(), file = dir + "/good.fsic";
  renderWith(scene, twoPass(file));
  const std::vector<char> good = readBytes(file);
  auto load = [&](const std::string&, const IrradianceCacheSettings& s, const RenderScene& sc) {
    IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
    ic.preprocess(sc);
  };

  std::vector<char> bad = good;
  bad[bad.size() / 2] ^= 0x10;  // one bit in a record
  writeBytes(dir + "/flipped.fsic", bad);
  expectRefused([&] { load("", twoPass(dir + "/flipped.fsic"), scene); }, dir + "/flipped.fsic", "corrupt");

  writeBytes(dir + "/short.fsic", std::vector<char>(good.begin(), good.end() - 100));
  expectRefused([&] { load("", twoPass(dir + "/short.fsic"), scene); }, dir + "/short.fsic", "truncated");

  test::writeText(dir + "/text.fsic", "these are not records\n");
  expectRefused([&] { load("", twoPass(dir + "/text.fsic"), scene); }, dir + "/text.fsic", "not an irradiance cache file");

  bad = good;
  bad[8] = 99;  // version
  writeBytes(dir + "/version.fsic", bad);
  expectRefused([&] { load("", twoPass(dir + "/version.fsic"), scene); }, dir + "/version.fsic", "format version");

  IrradianceCacheSettings other = twoPass(file);
  other.accuracy = 0.3f;
  expectRefused([&] { load("", other, scene); }, file, "different settings");
  other = twoPass(file);
  other.gradients = false;
  expectRefused([&] { load("", other, scene); }, file, "different settings");

  SceneDesc changed = desc;
  changed.materials[0].albedo.x *= 0.9f;
  const RenderScene changedScene(changed);
  expectRefused([&] { load("", twoPass(file), changedScene); }, file, "different scene");

  EXPECT_EQ(readBytes(file), good) << "a refused file is left alone";
  // The reader on its own, with the settings it was written with.
  IrradianceCacheIntegrator ic(IntegratorOptions{}, twoPass(file));
  ic.preprocess(scene);
  const CacheFileData d = readCacheFile(file, hashScene(desc), ic.settingsText());
  EXPECT_EQ(d.levels.size(), 2u);
}

TEST(IrradianceCacheFile, ToolExitsWithCode2AndNamesTheFile) {
#ifndef FIRSTSHOT_RENDER_EXE
  GTEST_SKIP() << "firstshot-render not built";
#else
  const std::string dir = test::tempDir(), file = dir + "/c.fsic", exe = FIRSTSHOT_RENDER_EXE;
  const std::string base = exe + " " + test::source("scenes/cornell.json") +
                           " --width 16 --height 16 --spp 1 -q --integrator irradiance-cache --ic-samples 64 --bounces 1";
  test::CommandResult r = test::run(base + " --two-pass --cache-file " + file + " -o " + dir + "/a.png --show-records " +
                                    dir + "/records.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  ASSERT_TRUE(std::filesystem::exists(file));
  std::vector<char> bytes = readBytes(file);
  bytes[bytes.size() - 20] ^= 1;
  writeBytes(file, bytes);
  r = test::run(base + " --cache-file " + file + " -o " + dir + "/b.png");
  fmt::print("{}", r.output);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find(file), std::string::npos);
  EXPECT_NE(r.output.find("corrupt"), std::string::npos);
  r = test::run(base + " --accuracy 0.3 --cache-file " + file + " -o " + dir + "/b.png");
  EXPECT_EQ(r.exitCode, 2) << "still corrupt";
  // Cache options belong to the irradiance cache integrator (--integrator auto would take it for them).
  r = test::run(exe + " " + test::source("scenes/cornell.json") + " --integrator path --width 8 --height 8 --spp 1 "
                "--accuracy 0.2 -o " + dir + "/c.png");
  fmt::print("{}", r.output);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find("--accuracy"), std::string::npos);
  r = test::run(base + " --clamp-footprint 5,1 -o " + dir + "/d.png");
  EXPECT_EQ(r.exitCode, 2) << r.output;
#endif
}

TEST(IrradianceCacheOnePass, SharedCacheFromTwoThreads) {
  // One cache filled by two render threads at once; the image agrees with the two-pass one.
  const RenderScene scene(test::cornellWithPointLight(kSize));
  IrradianceCacheSettings s = twoPass();
  const Rendered two = renderWith(scene, s, 2, 4);
  s.twoPass = false;
  const Rendered one = renderWith(scene, s, 2, 4);
  double a = 0, b = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) a += one.film.mean(x, y).y, b += two.film.mean(x, y).y;
  fmt::print("one pass: mean {:.5f}, {} records; two passes: mean {:.5f}, {} records\n", a / (kSize * kSize),
             one.stats.records, b / (kSize * kSize), two.stats.records);
  EXPECT_NEAR(a / b, 1.0, 0.02);
  EXPECT_NEAR(double(one.stats.records) / double(two.stats.records), 1.0, 0.3);
}

TEST(IrradianceCacheClamps, FootprintClampBoundsTheValidDomainInPixels) {
  const SceneDesc desc = test::cornellWithPointLight(kSize);
  const RenderScene scene(desc);
  const Vec3 eye(desc.camera.position);
  const double pixelAngle = 2.0 * std::tan(glm::radians(desc.camera.fovYDeg) / 2) / desc.camera.height;
  IrradianceCacheSettings s = twoPass();
  s.footprintMin = 2.0f;
  s.footprintMax = 4.0f;
  IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
  ic.preprocess(scene);
  const std::vector<IrradianceRecord> level0 = ic.cache().records(0), level1 = ic.cache().records(1);
  ASSERT_FALSE(level0.empty());
  double lo = 1e9, hi = 0;
  for (const IrradianceRecord& r : level0) {
    // Camera-visible records: the path length is the distance to the eye.
    const double px = ic.accuracy(0) * r.radius() / (pixelAngle * glm::length(r.p - eye));
    lo = std::min(lo, px), hi = std::max(hi, px);
  }
  double lo1 = 1e9;
  for (const IrradianceRecord& r : level1)  // deeper: the path is longer than the straight line
    lo1 = std::min(lo1, ic.accuracy(1) * r.radius() / (pixelAngle * glm::length(r.p - eye)));
  fmt::print("level 0 valid domains: {:.3f} to {:.3f} pixels; level 1 from {:.3f}\n", lo, hi, lo1);
  EXPECT_GE(lo, 2.0 * (1 - 1e-4));
  EXPECT_LE(hi, 4.0 * (1 + 1e-4));
  EXPECT_GE(lo1, 2.0 * (1 - 1e-4));
  // Without the clamp the domains shrink into the corners: more records.
  IrradianceCacheSettings off = s;
  off.footprintMin = 0.0f;
  off.footprintMax = std::numeric_limits<float>::infinity();
  IrradianceCacheIntegrator unclamped(IntegratorOptions{}, off);
  unclamped.preprocess(scene);
  fmt::print("level-0 records: {} clamped, {} unclamped\n", level0.size(), unclamped.cache().size(0));
  EXPECT_GT(unclamped.cache().size(0), level0.size());
}

TEST(IrradianceCacheClamps, NeighbourClampingLimitsRadiusJumps) {
  // Pairs of neighbouring level-0 records (each within the other's doubled domain) that break
  // R_i ≤ R_j + |P_i − P_j|: many without neighbour clamping, few with it.
  const RenderScene scene(test::cornellWithPointLight(kSize));
  auto violations = [&](bool clamp) {
    IrradianceCacheSettings s = twoPass();
    s.neighbourClamp = clamp;
    s.footprintMin = 0.0f;
    s.footprintMax = std::numeric_limits<float>::infinity();
    IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
    ic.preprocess(scene);
    const std::vector<IrradianceRecord> r = ic.cache().records(0);
    const float twoA = 2.0f * ic.accuracy(0);
    size_t pairs = 0, bad = 0;
    for (size_t i = 0; i < r.size(); ++i)
      for (size_t j = 0; j < r.size(); ++j) {
        const float d = glm::length(r[i].p - r[j].p);
        if (i == j || d >= twoA * r[j].R) continue;
        ++pairs;
        bad += r[i].R > r[j].R + d * 1.0001f;
      }
    fmt::print("neighbour clamping {}: {} records, {} of {} neighbouring pairs violate the bound\n", clamp ? "on" : "off",
               r.size(), bad, pairs);
    return std::pair<size_t, size_t>(bad, pairs);
  };
  const auto off = violations(false), on = violations(true);
  EXPECT_GT(off.first, 20u);
  // What remains comes from the fill's gap-filling sweep, whose records shrink no neighbour.
  EXPECT_LT(double(on.first), 0.25 * double(off.first));
}

TEST(IrradianceCacheRecords, RecordImageMarksVisibleRecords) {
  const RenderScene scene(test::cornellWithPointLight(kSize));
  IrradianceCacheIntegrator ic(IntegratorOptions{}, twoPass());
  ic.preprocess(scene);
  Film film(kSize, kSize);
  RenderOptions ro;
  ro.spp = 2;
  render(ic, Camera(scene.desc().camera), film, ro);
  const std::string dir = test::tempDir();
  film.write(dir + "/image.png", false);
  ic.writeRecordImage(film, dir + "/records.png");
  int w, h, w2, h2;
  std::vector<std::string> ch;
  const std::vector<float> image = Film::read(dir + "/image.png", w, h, ch), marked = Film::read(dir + "/records.png", w2, h2, ch);
  ASSERT_EQ(w, w2);
  ASSERT_EQ(image.size(), marked.size());
  const size_t c = ch.size();
  size_t blue = 0, changedOtherwise = 0;
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    const bool isBlue = marked[i * c] == 0.0f && marked[i * c + 1] == 0.0f && marked[i * c + 2] == 1.0f;
    if (isBlue)
      ++blue;
    else
      for (size_t k = 0; k < 3; ++k) changedOtherwise += marked[i * c + k] != image[i * c + k];
  }
  const size_t level0 = ic.cache().size(0);
  fmt::print("{} of {} pixels marked, {} level-0 records\n", blue, w * h, level0);
  EXPECT_GT(blue, 0u);
  EXPECT_LE(blue, level0);
  EXPECT_GT(blue, level0 / 4);  // most level-0 records are camera-visible (no mirrors here)
  EXPECT_EQ(changedOtherwise, 0u);
  // As an IntegratorRecord list for the preview: the level-0 records with their valid domains.
  const std::vector<IntegratorRecord> list = ic.records();
  ASSERT_EQ(list.size(), level0);
  EXPECT_NEAR(list[0].radius, ic.accuracy(0) * ic.cache().records(0)[0].radius(), 1e-7);
}
