// firstshot-render on the command line: the same EXR for --threads 1 and 2, the output formats
// (EXR with AOV layers, PNG), a clear error for a first-shot file of another scene, and bad options.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/util/error.h"
#include "render/output/film.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

// The binaries' paths come from this target's compile definitions, as in the other CLI tests.
const std::string kRender = FIRSTSHOT_RENDER_EXE;
const std::string kPreprocess = FIRSTSHOT_PREPROCESS_EXE;

std::string cornell() { return test::source("scenes/cornell.json"); }

/// Preprocesses @p scene into @p fsd with the Embree back end at a low resolution.
void preprocess(const std::string& scene, const std::string& fsd) {
  const auto r = test::run(kPreprocess + " " + scene + " -o " + fsd + " --backend embree --resolution 64 --patch-size 0.1 -q");
  ASSERT_EQ(r.exitCode, 0) << r.output;
}

std::vector<float> readImage(const std::string& path, int& w, int& h, std::vector<std::string>& channels) {
  return Film::read(path, w, h, channels);
}

size_t lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

}  // namespace

TEST(RenderCli, SameExrForOneAndTwoThreads) {
  const std::string dir = test::tempDir();
  preprocess(cornell(), dir + "/c.fsd");
  for (const std::string& extra : std::vector<std::string>{"", " --firstshot " + dir + "/c.fsd", " --firstshot " + dir + "/c.fsd --primary patch"}) {
    SCOPED_TRACE(extra);
    const std::string common = kRender + " " + cornell() + extra + " --spp 3 --width 24 --height 20 -q";
    const auto a = test::run(common + " --threads 1 -o " + dir + "/one.exr");
    const auto b = test::run(common + " --threads 2 -o " + dir + "/two.exr");
    ASSERT_EQ(a.exitCode, 0) << a.output;
    ASSERT_EQ(b.exitCode, 0) << b.output;
    int w1, h1, w2, h2;
    std::vector<std::string> c1, c2;
    const auto one = readImage(dir + "/one.exr", w1, h1, c1);
    const auto two = readImage(dir + "/two.exr", w2, h2, c2);
    EXPECT_EQ(w1, 24);
    EXPECT_EQ(h1, 20);
    EXPECT_EQ(one, two);
    EXPECT_TRUE(std::all_of(one.begin(), one.end(), [](float v) { return std::isfinite(v); }));
  }
}

TEST(RenderCli, ExrWithAovLayersAndPng) {
  const std::string dir = test::tempDir();
  const std::string common = kRender + " " + cornell() + " --spp 2 --width 16 --height 16 -q --aov";
  const auto r = test::run(common + " -o " + dir + "/img.exr -o " + dir + "/img.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  int w, h;
  std::vector<std::string> channels;
  const auto exr = readImage(dir + "/img.exr", w, h, channels);
  for (const char* c : {"R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z"})
    EXPECT_NE(std::find(channels.begin(), channels.end(), c), channels.end()) << c;
  // The normal layer holds unit vectors, or 0 where every sample left the (open) box.
  const size_t nc = channels.size();
  const size_t nx = size_t(std::find(channels.begin(), channels.end(), "normal.X") - channels.begin());
  size_t unit = 0;
  for (size_t p = 0; p < size_t(w) * h; ++p) {
    const float* n = &exr[p * nc + nx];
    const float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    EXPECT_TRUE(std::abs(len2 - 1.0f) < 1e-3f || len2 == 0.0f) << len2;
    unit += std::abs(len2 - 1.0f) < 1e-3f;
  }
  EXPECT_GT(unit, size_t(w) * h * 9 / 10);
  const auto png = readImage(dir + "/img.png", w, h, channels);
  EXPECT_EQ(channels.size(), 3u);
  EXPECT_EQ(w, 16);
  // Exposure brightens the PNG, not the EXR.
  ASSERT_EQ(test::run(common + " --exposure 2 -o " + dir + "/bright.png").exitCode, 0);
  const auto bright = readImage(dir + "/bright.png", w, h, channels);
  double sum = 0, sumBright = 0;
  for (size_t i = 0; i < png.size(); ++i) sum += png[i], sumBright += bright[i];
  EXPECT_GT(sumBright, 1.2 * sum);
  // No temporary files are left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir)) EXPECT_THAT(e.path().filename().string(), ::testing::Not(HasSubstr(".tmp")));
}

TEST(RenderCli, FirstShotFileOfAnotherSceneIsRejected) {
  const std::string dir = test::tempDir();
  preprocess(cornell(), dir + "/cornell.fsd");
  // The same scene with the light moved by 1 mm.
  std::ifstream in(cornell());
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto pos = text.find("0.343");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 5, "0.344");
  test::writeText(dir + "/moved.json", text);
  const auto r = test::run(kRender + " " + dir + "/moved.json --firstshot " + dir + "/cornell.fsd --spp 1 -q -o " + dir + "/x.exr");
  EXPECT_EQ(r.exitCode, kExitBadInput) << r.output;
  EXPECT_THAT(r.output, HasSubstr("cornell.fsd"));
  EXPECT_THAT(r.output, HasSubstr("different scene"));
  EXPECT_EQ(lines(r.output), 1u) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.exr"));
}

TEST(RenderCli, BadOptionsExitWithCode2) {
  const std::string dir = test::tempDir();
  const std::string base = kRender + " " + cornell() + " --width 8 --height 8 -q";
  for (const std::string& bad : std::vector<std::string>{" --spp 0 -o " + dir + "/a.exr", " --spp 2 --time 1 -o " + dir + "/a.exr",
                                " --integrator mlt -o " + dir + "/a.exr", " --primary sharp -o " + dir + "/a.exr",
                                " --spp 1 -o " + dir + "/a.jpg", " --spp 1", " --firstshot " + dir + "/none.fsd -o " + dir + "/a.exr"}) {
    const auto r = test::run(base + bad);
    EXPECT_EQ(r.exitCode, kExitBadInput) << bad << "\n" << r.output;
  }
  EXPECT_EQ(test::run(kRender + " " + dir + "/missing.json -o " + dir + "/a.exr").exitCode, kExitBadInput);
  EXPECT_FALSE(std::filesystem::exists(dir + "/a.exr"));
}

TEST(RenderCli, TimeLimitRendersWholePasses) {
  const std::string dir = test::tempDir();
  const auto r = test::run(kRender + " " + cornell() + " --width 8 --height 8 --time 0.05 -o " + dir + "/t.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("spp"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/t.exr"));
}
