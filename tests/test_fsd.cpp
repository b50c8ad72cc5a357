// The .fsd file: round trip, and a clear refusal of wrong magic or version, truncation, corruption
// and a scene mismatch. The command-line tool: CSV dump, exit codes, nothing half-written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/firstshot.h"
#include "common/scene_desc.h"
#include "tests/test_util.h"

using namespace fs;
using ::testing::HasSubstr;

namespace {

const std::string kExe = FIRSTSHOT_PREPROCESS_EXE;

/// A small table on the point-over-plane scene, made by the real tool.
std::string makeTable(const std::string& dir) {
  const std::string out = dir + "/pop.fsd";
  const auto r = test::run(kExe + " " + test::source("scenes/point-over-plane.json") + " -o " + out + " --resolution 64 --quiet");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  return out;
}

std::vector<char> readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<char>& b) {
  std::ofstream(path, std::ios::binary).write(b.data(), std::streamsize(b.size()));
}

std::string readError(const std::string& path, uint64_t hash = 0) {
  try {
    readFirstShot(path, hash);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    return e.what();
  }
  ADD_FAILURE() << "no error for " << path;
  return "";
}

}  // namespace

TEST(FsdFile, RoundTrip) {
  const std::string dir = test::tempDir();
  const std::string path = makeTable(dir);
  const SceneDesc scene = loadScene(test::source("scenes/point-over-plane.json"));
  const FirstShotTable t = readFirstShot(path, hashScene(scene));
  EXPECT_EQ(t.sceneHash, hashScene(scene));
  EXPECT_EQ(t.samples.size(), 1u);
  EXPECT_EQ(t.settings.resolution, 64u);
  EXPECT_EQ(t.mesh.size(), 400u);  // 2 m floor, 0.1 m patches
  EXPECT_EQ(t.rowStart.size(), 401u);
  writeFirstShot(dir + "/copy.fsd", t);
  EXPECT_EQ(readBytes(path), readBytes(dir + "/copy.fsd"));  // byte-identical rewrite
}

TEST(FsdFile, WrongMagic) {
  const std::string dir = test::tempDir();
  auto b = readBytes(makeTable(dir));
  b[0] = 'X';
  writeBytes(dir + "/bad.fsd", b);
  EXPECT_THAT(readError(dir + "/bad.fsd"), HasSubstr("wrong magic"));
}

TEST(FsdFile, WrongVersion) {
  const std::string dir = test::tempDir();
  auto b = readBytes(makeTable(dir));
  b[8] = 99;
  writeBytes(dir + "/bad.fsd", b);
  EXPECT_THAT(readError(dir + "/bad.fsd"), HasSubstr("format version 99"));
  b[8] = 1;  // a table from before the exposed-part factors: refused, with what to do
  writeBytes(dir + "/old.fsd", b);
  EXPECT_THAT(readError(dir + "/old.fsd"),
              HasSubstr("format version 1, this build reads version 3: run firstshot-preprocess again"));
}

TEST(FsdFile, Truncated) {
  const std::string dir = test::tempDir();
  auto b = readBytes(makeTable(dir));
  for (size_t keep : {size_t(4), size_t(40), b.size() / 2, b.size() - 1}) {
    std::vector<char> cut(b.begin(), b.begin() + long(keep));
    writeBytes(dir + "/cut.fsd", cut);
    EXPECT_THAT(readError(dir + "/cut.fsd"), ::testing::AnyOf(HasSubstr("truncated"), HasSubstr("wrong magic"))) << keep;
  }
}

TEST(FsdFile, CorruptByte) {
  const std::string dir = test::tempDir();
  auto b = readBytes(makeTable(dir));
  b[b.size() / 2] ^= 0x40;
  writeBytes(dir + "/bad.fsd", b);
  EXPECT_THAT(readError(dir + "/bad.fsd"), HasSubstr("checksum mismatch"));
}

TEST(FsdFile, SceneMismatch) {
  const std::string dir = test::tempDir();
  const std::string path = makeTable(dir);
  const SceneDesc other = loadScene(test::source("scenes/cornell.json"));
  EXPECT_THAT(readError(path, hashScene(other)), HasSubstr("different scene"));
}

TEST(FsdFile, MissingFile) { EXPECT_THAT(readError("/nonexistent/x.fsd"), HasSubstr("cannot open")); }

TEST(PreprocessCli, DumpCsvHasOneRowPerFactor) {
  const std::string dir = test::tempDir();
  const std::string path = makeTable(dir);
  const FirstShotTable t = readFirstShot(path);
  const auto r = test::run(kExe + " --dump-csv " + path);
  ASSERT_EQ(r.exitCode, 0);
  EXPECT_EQ(size_t(std::count(r.output.begin(), r.output.end(), '\n')), t.nonZeros() + 1);
  EXPECT_THAT(r.output, HasSubstr("patch,v0x,v0y,v0z"));
}

TEST(PreprocessCli, BadSceneWritesNothing) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/bad.json", "{\"materials\": {}, \"shapes\": [}");
  const auto r = test::run(kExe + " " + dir + "/bad.json -o " + dir + "/out.fsd");
  EXPECT_EQ(r.exitCode, kExitBadInput);
  EXPECT_THAT(r.output, HasSubstr("bad.json"));
  EXPECT_TRUE(std::filesystem::is_empty(dir + "/") || !std::filesystem::exists(dir + "/out.fsd"));
  for (const auto& e : std::filesystem::directory_iterator(dir)) EXPECT_EQ(e.path().extension(), ".json") << e.path();
}

TEST(PreprocessCli, CorruptFsdDumpExitsTwo) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/junk.fsd", "not a first-shot file at all, just text");
  const auto r = test::run(kExe + " --dump-csv " + dir + "/junk.fsd");
  EXPECT_EQ(r.exitCode, kExitBadInput);
  EXPECT_THAT(r.output, HasSubstr("junk.fsd"));
}

TEST(PreprocessCli, SummaryLine) {
  const std::string dir = test::tempDir();
  const auto r = test::run(kExe + " " + test::source("scenes/cornell.json") + " -o " + dir + "/c.fsd --resolution 32 --quiet --threads 2");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* part : {"light samples", "patches", "non-zero factors", "samples/s"}) EXPECT_THAT(r.output, HasSubstr(part));
}
