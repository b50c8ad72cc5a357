// Progress on the real binaries (common/util/progress.h): with stderr a pipe, plain lines (a start line,
// lines with percentage, done/total, elapsed time and ETA every FIRSTSHOT_PROGRESS_INTERVAL seconds,
// a closing line with the total time), never a carriage return or an escape code; --quiet: nothing
// on stderr. And a scene whose table has no patch at all (every surface emissive) preprocesses on
// every back end to an empty table that the renderer renders.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "common/table/firstshot.h"
#include "preprocess/gl/gl_context.h"
#include "render/output/film.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;
const std::string kPreprocess = FIRSTSHOT_PREPROCESS_EXE;
const std::string kCornell = test::source("scenes/cornell.json");
const std::string kFast = " --resolution 64 --threads 2";  ///< cornell's preprocessing in about a second

/// stderr alone of @p command (stdout dropped), read through a pipe; under the sanitizers without
/// LeakSanitizer's report of the suppressions it used.
test::CommandResult stderrOf(const std::string& command) {
  return test::run("(export LSAN_OPTIONS=\"${LSAN_OPTIONS:+$LSAN_OPTIONS:}print_suppressions=0\"; " + command + " 2>&1 >/dev/null)");
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// Checks the piped progress of one stage @p label in @p err: starts, at least one line with a
/// percentage in [0, 100] and an ETA, ends with its total time; no '\r', no ESC anywhere.
void expectProgressLines(const std::string& err, const std::string& label) {
  EXPECT_EQ(err.find('\r'), std::string::npos);
  EXPECT_EQ(err.find('\x1b'), std::string::npos);
  // Counts are units ("12/80") or, for a stage under a time limit, seconds ("0.1/0.3 s").
  const std::string count = R"(\(([\d.]+)/([\d.]+)(?: s)?\))";
  const std::string periodic = label + R"(: (\d+\.\d)% )" + count + R"(, \d+\.\d s elapsed, ETA (\d+\.\d s|unknown))";
  const std::string done = label + R"(: done in \d+\.\d\d s )" + count;
  int started = 0, withPercent = 0, finished = 0;
  for (const std::string& line : lines(err)) {
    if (line.rfind(label + ": started, ", 0) == 0) ++started;
    if (const auto m = test::regexMatch(line, periodic); !m.empty()) {
      ++withPercent;
      const double percent = std::stod(m[1]);
      EXPECT_GE(percent, 0.0) << line;
      EXPECT_LE(percent, 100.0) << line;
      EXPECT_LE(std::stod(m[2]), std::stod(m[3])) << line;
    }
    if (const auto m = test::regexMatch(line, done); !m.empty()) {
      ++finished;
      EXPECT_EQ(m[1], m[2]) << line;
    }
  }
  EXPECT_EQ(started, 1) << err;
  EXPECT_GE(withPercent, 1) << err;
  EXPECT_EQ(finished, 1) << err;
}

}  // namespace

TEST(ProgressCli, PipedPreprocessPrintsPlainLines) {
  const std::string dir = test::tempDir();
  const auto r = stderrOf("FIRSTSHOT_PROGRESS_INTERVAL=0.01 " + kPreprocess + " " + kCornell + kFast + " -o " + dir + "/c.fsd");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectProgressLines(r.output, "first-shot");
  // A stage ended early (here by --time) says where it stopped.
  const auto stopped = stderrOf("FIRSTSHOT_PROGRESS_INTERVAL=0.01 " + kPreprocess + " " + kCornell + kFast +
                                " --time 0.001 -o " + dir + "/d.fsd");
  EXPECT_NE(stopped.exitCode, 0);
  EXPECT_FALSE(test::regexSearch(stopped.output, R"(\nfirst-shot: stopped at \d+\.\d% \(\d+/80\) after )").empty())
      << stopped.output;
}

// A render under a time limit (0.3 s, so that lines at 0.01 s intervals come on any machine), then one
// of a fixed sample count.
TEST(ProgressCli, PipedRenderPrintsPlainLines) {
  const std::string dir = test::tempDir();
  const std::string render = "FIRSTSHOT_PROGRESS_INTERVAL=0.01 " + kRender + " " + kCornell +
                             " --width 64 --height 48 --threads 2 -o " + dir + "/c.exr";
  const auto timed = stderrOf(render + " --time 0.3");
  ASSERT_EQ(timed.exitCode, 0) << timed.output;
  expectProgressLines(timed.output, "render");
  // The limit left after the integrator's preprocessing (light trees), which --time counts.
  EXPECT_FALSE(test::regexSearch(timed.output, R"(render: started, time limit 0\.[0-3] s\n)").empty()) << timed.output;
  const auto counted = stderrOf(render + " --spp 64");
  ASSERT_EQ(counted.exitCode, 0) << counted.output;
  EXPECT_THAT(counted.output, HasSubstr("render: started, 196608 to do\n"));
  EXPECT_THAT(counted.output, HasSubstr(" (196608/196608)\n"));
}

TEST(ProgressCli, QuietPrintsNothingOnStderr) {
  const std::string dir = test::tempDir();
  const auto pre = stderrOf("FIRSTSHOT_PROGRESS_INTERVAL=0.01 " + kPreprocess + " " + kCornell + kFast + " --quiet -o " + dir +
                            "/c.fsd");
  ASSERT_EQ(pre.exitCode, 0) << pre.output;
  EXPECT_EQ(pre.output, "");
  const auto render = stderrOf("FIRSTSHOT_PROGRESS_INTERVAL=0.01 " + kRender + " " + kCornell + " --firstshot " + dir +
                               "/c.fsd --spp 4 --width 32 --height 24 --quiet -o " + dir + "/c.exr");
  ASSERT_EQ(render.exitCode, 0) << render.output;
  EXPECT_EQ(render.output, "");
}

// FIRSTSHOT_PROGRESS=1 forces the terminal's bar: redrawn in place with '\r', ended by a newline.
TEST(ProgressCli, ForcedBarRedrawsInPlace) {
  const std::string dir = test::tempDir();
  const auto r = stderrOf("FIRSTSHOT_PROGRESS=1 " + kRender + " " + kCornell +
                          " --spp 4 --width 32 --height 24 --threads 2 -o " + dir + "/c.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("\rrender [##############################] 100.0% 3072/3072 "));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("started")));
}

TEST(ProgressCli, BadIntervalIsBadInput) {
  for (const char* value : {"0", "-1", "abc", "5s", "nan"}) {
    const auto r = stderrOf(std::string("FIRSTSHOT_PROGRESS_INTERVAL=") + value + " " + kPreprocess + " " + kCornell +
                            kFast + " -o " + test::tempDir() + "/c.fsd");
    EXPECT_EQ(r.exitCode, 2) << value << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr("FIRSTSHOT_PROGRESS_INTERVAL")) << value;
    EXPECT_EQ(lines(r.output).size(), 1u) << r.output;
  }
}

// Only emitters and a point light: no surface becomes a patch. Every back end writes a table of the
// light samples and no patch; the renderer accepts it and sees the lamp's radiance (5) directly.
TEST(ProgressCli, SceneWithoutPatchesPreprocessesOnEveryBackEnd) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/lamps.json", R"({
    "camera": {"position": [0, 2, 0.001], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60, "resolution": [16, 16]},
    "materials": {"lamp": {"type": "diffuse", "emission": 5}},
    "shapes": [{"type": "quad", "material": "lamp", "small": true,
                "vertices": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]}],
    "lights": [{"type": "point", "position": [0, 1, 0], "power": 10}],
    "settings": {"spp": 2, "item_buffer_resolution": 32, "light_patch_size": 1}})");
  bool egl = true;
  try {
    GLContext probe(GLBackend::EGL);
  } catch (const std::exception&) {
    egl = false;  // (test_item_buffer's EglSurfacelessWorks reports the skip)
  }
  for (const std::string backend : {"gl --gl osmesa", "gl --gl egl", "embree", "auto"}) {
    if (backend == "gl --gl egl" && !egl) continue;
    SCOPED_TRACE(backend);
    const std::string fsd = dir + "/lamps.fsd", exr = dir + "/lamps.exr";
    const auto pre = test::run(kPreprocess + " " + dir + "/lamps.json -q --backend " + backend + " -o " + fsd);
    ASSERT_EQ(pre.exitCode, 0) << pre.output;
    const FirstShotTable t = readFirstShot(fsd);
    EXPECT_EQ(t.mesh.size(), 0u);
    EXPECT_EQ(t.replacedLights.size(), 2u);
    EXPECT_GE(t.samples.size(), 5u);  // the point light and the quad's 4 vertices at least
    EXPECT_TRUE(t.factor.empty());
    const auto render = test::run(kRender + " " + dir + "/lamps.json -q --firstshot " + fsd + " -o " + exr);
    ASSERT_EQ(render.exitCode, 0) << render.output;
    int w = 0, h = 0;
    std::vector<std::string> channels;
    const std::vector<float> px = Film::read(exr, w, h, channels);
    ASSERT_EQ(w * h, 256);
    const size_t c = channels.size();
    const size_t centre = (size_t(h / 2) * size_t(w) + size_t(w / 2)) * c;
    for (size_t k = 0; k < 3; ++k) EXPECT_NEAR(px[centre + k], 5.0f, 1e-5f) << channels[k];
  }
}
