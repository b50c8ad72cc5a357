// SIGINT and SIGTERM on the real binaries (common/util/interrupt.h): firstshot-render and
// firstshot-preprocess stop with exit code 130 / 143 and a message, and leave no output and no
// temporary file, also when the signal comes while an output or the irradiance cache file is being
// written; firstshot-render --checkpoint / --resume continues an interrupted render to the same
// image, bit for bit, for every integrator (with the default sampler, sobol, whose sample index must continue
// across the resume), and refuses a checkpoint of another render (exit 2).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "render/output/film.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

// The binaries' paths come from this target's compile definitions, as in the other CLI tests.
const std::string kRender = FIRSTSHOT_RENDER_EXE;
const std::string kPreprocess = FIRSTSHOT_PREPROCESS_EXE;
const std::string kCornell = test::source("scenes/cornell.json");
const std::string kSmall = " --width 32 --height 24 -q";

/// @p command with signal @p sig (INT, TERM) sent @p seconds after it has installed its handlers
/// and, if @p waitFile is given, that file exists (tests/signal_when_ready.sh).
std::string after(double seconds, const std::string& sig, const std::string& command, const std::string& waitFile = "") {
  return test::source("tests/signal_when_ready.sh") + " " + sig + " " + std::to_string(seconds) +
         (waitFile.empty() ? "" : " --wait-file " + waitFile) + " " + command;
}

/// The files in @p dir (names).
std::vector<std::string> files(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<float> pixels(const std::string& path) {
  int w = 0, h = 0;
  std::vector<std::string> channels;
  return Film::read(path, w, h, channels);
}

}  // namespace

TEST(InterruptCli, RenderStopsOnSigintAndSigtermWritingNothing) {
  for (const auto& [sig, code] : {std::pair{"INT", 130}, std::pair{"TERM", 143}}) {
    const std::string dir = test::tempDir();
    const auto r = test::run(after(1, sig, kRender + " " + kCornell + " --spp 1000000 --threads 1" + kSmall + " -o " + dir +
                                               "/a.exr -o " + dir + "/a.png"));
    EXPECT_EQ(r.exitCode, code) << r.output;
    EXPECT_THAT(r.output, HasSubstr(std::string("firstshot-render: interrupted by SIG") + sig + "; no output written"));
    EXPECT_TRUE(files(dir).empty()) << ::testing::PrintToString(files(dir));
  }
}

TEST(InterruptCli, PreprocessStopsOnSigintWritingNothing) {
  const std::string dir = test::tempDir();
  // About 18 s uninterrupted in Release.
  const auto r = test::run(after(1, "INT", kPreprocess + " " + kCornell + " --backend embree --resolution 512 --patch-size 0.05 "
                                                        "--threads 1 -q -o " + dir + "/c.fsd"));
  EXPECT_EQ(r.exitCode, 130) << r.output;
  EXPECT_THAT(r.output, HasSubstr("firstshot-preprocess: interrupted by SIGINT; no output written"));
  EXPECT_TRUE(files(dir).empty()) << ::testing::PrintToString(files(dir));
}

TEST(InterruptCli, SignalWhileWritingAnOutputLeavesNeitherItNorItsTemporaryFile) {
  const std::string dir = test::tempDir();
  const std::string hook = "FIRSTSHOT_TEST_INTERRUPT=";
  // The signal arrives once the temporary file is complete, before the rename.
  auto r = test::run(hook + "write-c.fsd " + kPreprocess + " " + kCornell + " --backend embree --resolution 32 -q -o " + dir + "/c.fsd");
  EXPECT_EQ(r.exitCode, 130) << r.output;
  EXPECT_THAT(r.output, HasSubstr("c.fsd was not written"));
  EXPECT_TRUE(files(dir).empty()) << ::testing::PrintToString(files(dir));

  r = test::run(hook + "write-a.exr:TERM " + kRender + " " + kCornell + " --spp 1" + kSmall + " -o " + dir + "/a.exr");
  EXPECT_EQ(r.exitCode, 143) << r.output;
  EXPECT_THAT(r.output, HasSubstr("interrupted by SIGTERM"));
  EXPECT_TRUE(files(dir).empty()) << ::testing::PrintToString(files(dir));

  // The irradiance cache file is written after the image.
  r = test::run(hook + "write-c.fsic " + kRender + " " + kCornell + " --integrator irradiance-cache --ic-samples 16 --bounces 1 "
                "--spp 1 --cache-file " + dir + "/c.fsic" + kSmall + " -o " + dir + "/a.exr");
  EXPECT_EQ(r.exitCode, 130) << r.output;
  EXPECT_THAT(r.output, HasSubstr("c.fsic was not written"));
  EXPECT_EQ(files(dir), std::vector<std::string>{"a.exr"});
}

class InterruptResume : public ::testing::TestWithParam<std::string> {};

/// Interrupted after two passes (the signal raised by the test hook at the pass boundary), resumed.
TEST_P(InterruptResume, ResumedImageEqualsTheUninterruptedOne) {
  const std::string dir = test::tempDir();
  std::string it = " --integrator " + GetParam();
  if (GetParam() == "irradiance-cache") it += " --two-pass --ic-samples 32 --bounces 1";
  const std::string base = kRender + " " + kCornell + it + " --spp 5 --threads 2" + kSmall;
  ASSERT_EQ(test::run(base + " -o " + dir + "/full.exr").exitCode, 0);
  const auto stopped = test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-2 " + base + " --checkpoint 1000 -o " + dir + "/a.exr");
  EXPECT_EQ(stopped.exitCode, 130) << stopped.output;
  EXPECT_THAT(stopped.output, HasSubstr("checkpoint of 2 passes saved to " + dir + "/a.exr.checkpoint"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/a.exr"));
  const auto resumed = test::run(base + " --resume -o " + dir + "/a.exr");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_EQ(pixels(dir + "/a.exr"), pixels(dir + "/full.exr"));
  EXPECT_EQ(files(dir), (std::vector<std::string>{"a.exr", "full.exr"})) << "the checkpoint is deleted when done";
}

INSTANTIATE_TEST_SUITE_P(EveryIntegrator, InterruptResume,
                         ::testing::Values("path", "irradiance-cache", "light", "bundle", "bdpt"), [](const auto& p) {
                           std::string n = p.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

/// A real SIGINT at an arbitrary moment (possibly in the middle of a pass), with periodic checkpoints.
TEST(InterruptCli, SigintWithPeriodicCheckpointsResumesExactly) {
  const std::string dir = test::tempDir();
  // The path tracer named: --integrator auto's pilot for a million spp would take the half second before the signal.
  const std::string base = kRender + " " + kCornell + " --integrator path --threads 2 --checkpoint-file " + dir + "/state" +
                           kSmall;
  const auto stopped = test::run(after(0.5, "INT", base + " --spp 1000000 --checkpoint 0.1 -o " + dir + "/a.exr", dir + "/state"));
  ASSERT_EQ(stopped.exitCode, 130) << stopped.output;
  const auto m = test::regexSearch(stopped.output, "checkpoint of ([0-9]+) passes saved to " + dir + "/state");
  ASSERT_FALSE(m.empty()) << stopped.output;
  const std::string spp = " --spp " + std::to_string(std::stoi(m[1]) + 3);
  const auto resumed = test::run(base + spp + " --resume -o " + dir + "/a.exr");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  ASSERT_EQ(test::run(kRender + " " + kCornell + " --integrator path" + spp + kSmall + " -o " + dir + "/full.exr").exitCode,
            0);
  EXPECT_EQ(pixels(dir + "/a.exr"), pixels(dir + "/full.exr"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/state"));
}

/// With --time the passes count: the resumed image equals the --spp render of the total printed.
TEST(InterruptCli, ResumeWithTimeLimitEqualsTheRenderOfItsPassCount) {
  const std::string dir = test::tempDir();
  // The path tracer named: with --integrator auto a --time render and the --spp render of its passes may choose
  // differently (the resumed render takes the checkpoint's choice: IntegratorAuto.ResumeTakesTheCheckpointsChoice).
  const std::string base = kRender + " " + kCornell + " --integrator path --width 32 --height 24 --threads 2";
  const auto stopped = test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-2 " + base + " --time 100 -q --checkpoint 1000 -o " + dir + "/a.exr");
  ASSERT_EQ(stopped.exitCode, 130) << stopped.output;
  const auto resumed = test::run(base + " --time 0.2 --resume -o " + dir + "/a.exr");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  const auto m = test::regexSearch(resumed.output, "32x24 at ([0-9]+) spp");
  ASSERT_FALSE(m.empty()) << resumed.output;
  EXPECT_GT(std::stoi(m[1]), 2);
  ASSERT_EQ(test::run(base + " -q --spp " + m[1] + " -o " + dir + "/full.exr").exitCode, 0);
  EXPECT_EQ(pixels(dir + "/a.exr"), pixels(dir + "/full.exr"));
}

TEST(InterruptCli, ResumeRefusesACheckpointOfAnotherRenderWithCode2) {
  const std::string dir = test::tempDir();
  const std::string base = kRender + " " + kCornell + " --spp 4 --height 24 -q";
  ASSERT_EQ(test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-1 " + base + " --width 32 --checkpoint 1000 -o " + dir + "/a.exr").exitCode, 130);
  const std::string checkpoint = dir + "/a.exr.checkpoint";
  ASSERT_TRUE(std::filesystem::exists(checkpoint));
  for (const auto& [change, what] : {std::pair{" --width 32 --seed 9", "seed is \"1\" in the checkpoint but \"9\" now"},
                                     std::pair{" --width 32 --integrator bdpt", "integrator is \"path\" in the checkpoint but \"bdpt\" now"},
                                     std::pair{" --width 32 --primary patch", "--primary is \"exact\" in the checkpoint but \"patch\" now"},
                                     std::pair{" --width 33", "width is \"32\" in the checkpoint but \"33\" now"}}) {
    const auto r = test::run(base + change + " --resume -o " + dir + "/a.exr");
    EXPECT_EQ(r.exitCode, 2) << change << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr(checkpoint + ": key: made for a different render: " + what)) << change;
  }
  // The same scene with the light moved by 1 mm.
  std::string text = test::readFile(kCornell);
  ASSERT_NE(text.find("0.343"), std::string::npos);
  text.replace(text.find("0.343"), 5, "0.344");
  test::writeText(dir + "/moved.json", text);
  const auto moved = test::run(kRender + " " + dir + "/moved.json --spp 4 --height 24 -q --width 32 --resume -o " + dir + "/a.exr");
  EXPECT_EQ(moved.exitCode, 2) << moved.output;
  EXPECT_THAT(moved.output, HasSubstr(checkpoint + ": key: made for a different render: scene-file is"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/a.exr"));
  // The checkpoint survives the failed attempts and still resumes.
  EXPECT_EQ(test::run(base + " --width 32 --resume -o " + dir + "/a.exr").exitCode, 0);
}

TEST(InterruptCli, CheckpointOptionsRefusedWhereTheyCannotWork) {
  const std::string dir = test::tempDir();
  const std::string base = kRender + " " + kCornell + " --spp 4" + kSmall + " -o " + dir + "/b.exr";
  using Case = std::pair<std::string, std::string>;  // options, message
  for (const auto& [bad, message] :
       {Case{" --resume", dir + "/b.exr.checkpoint: cannot open the checkpoint file"},
        Case{" --integrator irradiance-cache --one-pass --checkpoint 1", "cannot resume exactly: drop --one-pass"},
        Case{" --checkpoint-file " + dir + "/x", "--checkpoint-file: only with --checkpoint or --resume"}}) {
    const auto r = test::run(base + bad);
    EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr(message)) << bad;
  }
  EXPECT_TRUE(files(dir).empty());
}
