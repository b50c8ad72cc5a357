// The hard cases that must be refused (docs/robustness.md "Hard cases"): through the real tools, a
// NaN vertex in a mesh file (a degenerate face is skipped, not refused), more patches than 32-bit IDs allow or than memory
// holds, an item-buffer resolution or an image that cannot fit in memory give one line naming the
// file and the place, exit code 2, at once, and no output file. Plus every scene of the suite that
// must work goes through both tools (preprocess, then render with the path tracer and the
// irradiance cache) to a finite image.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "common/util/error.h"
#include "common/util/memory_limit.h"
#include "render/output/film.h"
#include "tests/hard_cases.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

const std::string kPreprocess = FIRSTSHOT_PREPROCESS_EXE;
const std::string kRender = FIRSTSHOT_RENDER_EXE;

/// One line on stderr naming the scene file and every one of @p parts, exit code 2.
void expectRefused(const test::CommandResult& r, const std::string& file, std::initializer_list<const char*> parts) {
  EXPECT_EQ(r.exitCode, kExitBadInput) << r.output;
  EXPECT_THAT(r.output, HasSubstr(file)) << "the message names the file";
  for (const char* p : parts) EXPECT_THAT(r.output, HasSubstr(p));
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
}

struct Refusal {
  const char* file;
  std::initializer_list<const char*> parts;
};

/// Runs both tools on @p c's scene (with @p extra options, and @p renderExtra for the renderer) and expects both
/// to refuse it, writing nothing.
void expectBothToolsRefuse(const Refusal& c, const std::string& extra = "", const std::string& renderExtra = "") {
  const std::string dir = test::tempDir(), scene = test::hardCasePath(c.file);
  SCOPED_TRACE(c.file);
  expectRefused(test::run(kPreprocess + " " + scene + " -o " + dir + "/out.fsd --backend embree --quiet " + extra), c.file, c.parts);
  expectRefused(test::run(kRender + " " + scene + " -o " + dir + "/out.exr --spp 1 --quiet " + extra + " " + renderExtra), c.file,
                c.parts);
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.fsd"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.exr"));
}

/// A patch size far too small does not concern a render without a table, which traces the faces as they are;
/// the bundle integrator, whose elements are patches, builds them and refuses it (expectBothToolsRefuse).
void expectRenderWithoutTableIgnoresPatchSize(const std::string& file) {
  const std::string dir = test::tempDir();
  const auto r = test::run(kRender + " " + test::hardCasePath(file) + " -o " + dir + "/out.exr --spp 1 --quiet");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/out.exr"));
}

}  // namespace

TEST(HardCaseErrors, NaNVertexInMesh) {
  expectBothToolsRefuse({"nan_mesh.json", {"shapes[0]", "vertex 4 of", "nan_vertex.obj", "not finite"}});
}

TEST(HardCaseErrors, DegenerateFaceInMeshIsSkipped) {
  // Not refused any more: other renderers tolerate a zero-area triangle, so both tools skip it with one line on
  // stderr and go on (docs/scene-format.md, "Skipped faces").
  const std::string dir = test::tempDir(), scene = test::hardCasePath("degenerate_mesh.json");
  for (const std::string& command : {kPreprocess + " " + scene + " -o " + dir + "/out.fsd --backend embree --quiet",
                                     kRender + " " + scene + " -o " + dir + "/out.exr --spp 1 --quiet"}) {
    const auto r = test::run(command);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("degenerate_mesh.json: skipped 1 of 2 triangles of "));
    EXPECT_THAT(r.output, HasSubstr("degenerate_face.obj (1 zero-area, 0 duplicates)"));
  }
}

TEST(HardCaseErrors, MorePatchesThan32BitIds) {
  expectBothToolsRefuse({"too_many_patches.json", {"settings.patch_size", "1e+14 patches", "2^32-1"}}, "", "--integrator bundle");
  expectRenderWithoutTableIgnoresPatchSize("too_many_patches.json");
}

TEST(HardCaseErrors, PatchesThatCannotFitInMemory) {
  // 3.9e9 patches of sizeof(Patch) bytes: about 300 GB.
  if (double(physicalMemoryBytes()) > 3.9e9 * sizeof(Patch)) GTEST_SKIP() << "this machine could hold them";
  expectBothToolsRefuse({"patches_exceed_memory.json", {"settings.patch_size", "3.91e+09 patches", "GB", "memory"}}, "",
                        "--integrator bundle");
  expectRenderWithoutTableIgnoresPatchSize("patches_exceed_memory.json");
}

/// The InputError message preprocessScene gives for @p desc at item-buffer resolution @p R ("" if none).
std::string preprocessError(const SceneDesc& desc, uint32_t R, const std::string& window) {
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.settings.resolution = R;
  po.settings.window = window;
  po.threads = 1;
  po.quiet = true;
  try {
    preprocessScene(desc, po);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The command line and the scene file cap R at 8192 (CLI11 and the JSON reader: exit 2); the library
// checks it too.
TEST(HardCaseErrors, ItemBufferResolutionOutOfRange) {
  const auto r = test::run(kPreprocess + " " + test::hardCasePath("point_near_wall.json") + " -o " +
                           test::tempDir() + "/out.fsd --quiet --resolution 1000000");
  EXPECT_EQ(r.exitCode, kExitBadInput) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--resolution: Value 1000000 not in range 2 to 8192"));
  const SceneDesc desc = test::loadHardCase("point_near_wall.json");
  EXPECT_THAT(preprocessError(desc, 1000000, "hemicube"),
              HasSubstr("point_near_wall.json: settings.item_buffer_resolution (--resolution): R = 1000000 is outside [2, 16384]"));
}

TEST(HardCaseErrors, ItemBuffersThatCannotFitInMemory) {
  // R = 16384 with the cubic tetrahedron: (6 + 8)·R² weights of 8 bytes and 2R² IDs of 4: 32 GB.
  if (double(physicalMemoryBytes()) > (8.0 * 14 + 8.0) * 16384.0 * 16384.0) GTEST_SKIP() << "this machine could hold them";
  const SceneDesc desc = test::loadHardCase("point_near_wall.json");
  const std::string message = preprocessError(desc, 16384, "tetra");
  EXPECT_THAT(message, HasSubstr("point_near_wall.json: settings.item_buffer_resolution (--resolution): needs 32.2 GB for "
                                 "item buffers of R = 16384"));
}

TEST(HardCaseErrors, ImageThatCannotFitInMemory) {
  // 65536² pixels of 100 bytes: 430 GB (the scene's own 32768² is 107 GB).
  if (double(physicalMemoryBytes()) > 65536.0 * 65536.0 * 100) GTEST_SKIP() << "this machine could hold it";
  const std::string dir = test::tempDir();
  const auto r = test::run(kRender + " " + test::hardCasePath("huge_image.json") + " -o " + dir +
                           "/out.exr --spp 1 --quiet --width 65536 --height 65536");
  expectRefused(r, "huge_image.json", {"image size: needs 429 GB for 65536×65536 pixels", "--width, --height"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.exr"));
  EXPECT_THROW(Film(65536, 65536), InputError);
}

/// Every scene of the suite that must work, through both tools: preprocess to a .fsd, render it with
/// the path tracer and the irradiance cache to EXR; exit code 0 and every pixel finite.
class HardCaseTools : public ::testing::TestWithParam<const char*> {};

TEST_P(HardCaseTools, PreprocessAndRenderToFiniteImages) {
  const std::string dir = test::tempDir(), scene = test::hardCasePath(GetParam());
  const auto pre = test::run(kPreprocess + " " + scene + " -o " + dir + "/case.fsd --backend embree --resolution 64 --quiet");
  ASSERT_EQ(pre.exitCode, 0) << pre.output;
  for (const char* integrator : test::kHardCaseIntegrators) {
    SCOPED_TRACE(integrator);
    const std::string image = dir + "/" + integrator + ".exr";
    const auto r = test::run(kRender + " " + scene + " --firstshot " + dir + "/case.fsd --integrator " + integrator +
                             " --spp 2 --quiet -o " + image);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    int w = 0, h = 0;
    std::vector<std::string> channels;
    const std::vector<float> pixels = Film::read(image, w, h, channels);
    ASSERT_EQ(pixels.size(), size_t(w) * h * channels.size());
    for (size_t i = 0; i < pixels.size(); ++i) ASSERT_TRUE(std::isfinite(pixels[i])) << "value " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(HardCases, HardCaseTools,
                         ::testing::Values("point_near_wall.json", "light_coplanar.json", "tiny_patches.json",
                                           "grazing_light.json", "albedo0_box.json", "albedo1_box.json",
                                           "albedo1_box_point.json", "scale_unit.json", "scale_1e-3.json", "scale_1e4.json"),
                         [](const auto& p) {
                           std::string s = p.param;
                           s = s.substr(0, s.rfind('.'));
                           for (char& ch : s)
                             if (ch == '-') ch = 'm';
                           return s;
                         });
