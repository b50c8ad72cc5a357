// The .fsd file: round trip, and a clear refusal of wrong magic or version, truncation, corruption
// and a scene mismatch. The command-line tool: CSV dump, exit codes, nothing half-written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <tuple>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "common/util/error.h"
#include "common/util/hash.h"
#include "tests/test_util.h"

using namespace firstshot;
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

/// A table with grouped factors (an area light): the Cornell box at R = 32, made once by the real tool.
const std::string& groupedTable() {
  static const std::string path = [] {
    const std::string out = test::tempDir() + "/cornell.fsd";
    const auto r = test::run(kExe + " " + test::source("scenes/cornell.json") + " -o " + out +
                             " --resolution 32 --quiet --threads 2");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return out;
  }();
  return path;
}

/// The arrays of a file's CSRR section (docs/firstshot-format.md), as byte offsets into the file.
struct CsrrLayout {
  size_t rowCount, singleCount, groupCount, singleSample, singleFactor, groupLight, groupVisible;
  uint64_t singles, groups;
};

CsrrLayout csrrLayout(const std::vector<char>& b, uint64_t patches) {
  size_t p = 40;  // magic, version, flags, three hashes
  for (;;) {
    uint64_t len;
    std::memcpy(&len, b.data() + p + 4, 8);
    if (std::memcmp(b.data() + p, "CSRR", 4) == 0) break;
    p += 12 + len;
  }
  p += 12;
  CsrrLayout l{};
  std::memcpy(&l.singles, b.data() + p + 8, 8);
  std::memcpy(&l.groups, b.data() + p + 16, 8);
  l.rowCount = p + 32;
  l.singleCount = l.rowCount + 4 * patches;
  l.groupCount = l.singleCount + 4 * patches;
  l.singleSample = l.groupCount + 4 * patches;
  l.singleFactor = l.singleSample + 4 * l.singles;
  l.groupLight = l.singleFactor + 4 * l.singles;
  l.groupVisible = l.groupLight + 4 * l.groups;
  return l;
}

template <typename T>
void poke(std::vector<char>& b, size_t offset, T v) {
  std::memcpy(b.data() + offset, &v, sizeof(T));
}

/// Writes @p b with its checksum recomputed, so that the reader gets past it to the contents.
void writeResealed(const std::string& path, std::vector<char> b) {
  poke(b, b.size() - 16, Hasher().bytes(b.data(), b.size() - 16).value());
  writeBytes(path, b);
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
              HasSubstr("format version 1, this build reads version 8: run firstshot-preprocess again"));
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

// Version 3's grouped factors: every malformed group is refused, naming the file and the section.
TEST(FsdFile, MalformedGroupsAreRefused) {
  const std::string& good = groupedTable();
  const FirstShotTable t = readFirstShot(good);
  const std::vector<char> b = readBytes(good);
  const CsrrLayout l = csrrLayout(b, t.mesh.size());
  ASSERT_GT(l.groups, 0u);
  ASSERT_GT(l.singles, 0u);
  // The first row with a group (its group is the file's first), and one after it.
  const uint64_t group = 0;
  uint32_t row = 0;
  for (;; ++row) {
    uint32_t c;
    std::memcpy(&c, b.data() + l.groupCount + 4 * row, 4);
    if (c > 0) break;
  }
  ASSERT_LT(row + 1, t.mesh.size());
  const std::string dir = test::tempDir();
  const std::string bad = dir + "/bad.fsd";
  auto refused = [&](std::vector<char> m, const std::string& what) {
    writeResealed(bad, std::move(m));
    const std::string e = readError(bad);
    EXPECT_THAT(e, HasSubstr("CSRR"));
    EXPECT_THAT(e, HasSubstr(what));
  };
  {  // a light that has no area-light vertices
    auto m = b;
    poke<uint32_t>(m, l.groupLight + 4 * group, 12345);
    refused(m, "has no area-light vertices");
  }
  for (float v : {0.0f, -0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN()}) {  // V outside (0, 1]
    auto m = b;
    poke<float>(m, l.groupVisible + 4 * group, v);
    refused(m, "visible fraction outside (0, 1]");
  }
  {  // a single entry's sample out of range
    auto m = b;
    poke<uint32_t>(m, l.singleSample, uint32_t(t.samples.size()));
    refused(m, "is invalid");
  }
  {  // a row claiming one factor more than its entries expand to (and the next one fewer)
    auto m = b;
    uint32_t c0, c1;
    std::memcpy(&c0, m.data() + l.rowCount + 4 * row, 4);
    std::memcpy(&c1, m.data() + l.rowCount + 4 * (row + 1), 4);
    poke<uint32_t>(m, l.rowCount + 4 * row, c0 + 1);
    poke<uint32_t>(m, l.rowCount + 4 * (row + 1), c1 - 1);
    refused(m, "row " + std::to_string(row) + ": its entries expand to");
  }
  {  // group counts that do not add up
    auto m = b;
    uint32_t c;
    std::memcpy(&c, m.data() + l.groupCount + 4 * row, 4);
    poke<uint32_t>(m, l.groupCount + 4 * row, c + 1);
    refused(m, "group counts do not add up");
  }
  {  // a sample listed both as a single and in a group: the next single entry after the first grouped row moved
     // into that row (its count and the row lengths changed, no bytes moved), made a vertex of the group's light
    auto m = b;
    auto count = [&](size_t array, uint32_t j) {
      uint32_t c;
      std::memcpy(&c, m.data() + array + 4 * j, 4);
      return c;
    };
    uint64_t single = 0;
    for (uint32_t j = 0; j < row; ++j) single += count(l.singleCount, j);
    uint32_t next = row;
    while (next < t.mesh.size() && count(l.singleCount, next) == 0) ++next;
    ASSERT_LT(next, t.mesh.size());
    ASSERT_GT(next, row) << "the first grouped row has single entries too";
    poke<uint32_t>(m, l.singleCount + 4 * row, 1);
    poke<uint32_t>(m, l.singleCount + 4 * next, count(l.singleCount, next) - 1);
    poke<uint32_t>(m, l.rowCount + 4 * row, count(l.rowCount, row) + 1);
    poke<uint32_t>(m, l.rowCount + 4 * next, count(l.rowCount, next) - 1);
    uint32_t light;
    std::memcpy(&light, m.data() + l.groupLight + 4 * group, 4);
    uint32_t vertex = 0;  // a vertex of the light that the group expands to in the row
    for (uint64_t k = t.rowStart[row]; k < t.rowStart[row + 1]; ++k)
      if (t.samples[t.sampleIndex[k]].light == light) vertex = t.sampleIndex[k];
    poke<uint32_t>(m, l.singleSample + 4 * single, vertex);
    refused(m, "row " + std::to_string(row) + ": light samples not ascending or listed twice");
  }
  EXPECT_NO_THROW(readFirstShot(good));
}

// A table without groups (a point light) carries neither the single nor the group counts.
TEST(FsdFile, TableWithoutGroupsHasNoGroupArrays) {
  const std::string dir = test::tempDir();
  const std::string path = makeTable(dir);
  const FirstShotTable t = readFirstShot(path);
  const std::vector<char> b = readBytes(path);
  const CsrrLayout l = csrrLayout(b, t.mesh.size());
  EXPECT_EQ(l.groups, 0u);
  EXPECT_EQ(l.singles, t.nonZeros());
  // rowCount, then straight to the singles: 4 bytes per row and 8 per factor, then the empty LUMN section (tag,
  // length, count 0), checksum and end marker.
  EXPECT_EQ(b.size(), l.rowCount + 4 * t.mesh.size() + 8 * t.nonZeros() + 20 + 16);
}

namespace {

/// A hand-made table of five patches: two runs of (shape, material) that come back, triangles and
/// quads sharing corners, and a corner at -0 beside one at +0 (distinct bit patterns).
FirstShotTable packedPatchesTable() {
  FirstShotTable t;
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0), e(2, 0, 0), z(-0.0f, 0, 0);
  auto patch = [](std::initializer_list<Vec3> v, uint32_t shape, uint32_t material) {
    Patch p;
    p.count = uint32_t(v.size()), p.shape = shape, p.material = material;
    std::copy(v.begin(), v.end(), p.v);
    if (p.count == 3) p.v[3] = p.v[2];
    computePatchGeometry(p);
    return p;
  };
  t.mesh.patches = {patch({a, b, c, d}, 0, 1), patch({b, e, c}, 0, 1), patch({z, b, c}, 2, 0),
                    patch({a, b, c}, 2, 0), patch({d, a, e, c}, 0, 1)};
  t.mesh.patchSize = 0.5;
  t.rowStart.assign(t.mesh.patches.size() + 1, 0);
  return t;
}

/// Byte offset of section @p tag's contents (after its tag and length) in a table's bytes.
size_t sectionContents(const std::vector<char>& b, const char* tag) {
  size_t p = 40;  // magic, version, flags, three hashes
  for (;;) {
    uint64_t len;
    std::memcpy(&len, b.data() + p + 4, 8);
    if (std::memcmp(b.data() + p, tag, 4) == 0) return p + 12;
    p += 12 + len;
  }
}

}  // namespace

TEST(FsdFile, PackedPatchesComeBackBitForBit) {
  const std::string path = test::tempDir() + "/packed.fsd";
  const FirstShotTable t = packedPatchesTable();
  writeFirstShot(path, t);
  const FirstShotTable r = readFirstShot(path);
  ASSERT_EQ(r.mesh.size(), t.mesh.size());
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const Patch &p = t.mesh.patches[j], &q = r.mesh.patches[j];
    EXPECT_EQ(std::memcmp(p.v, q.v, sizeof(p.v)), 0) << j;  // -0 stays -0; a triangle's 4th corner its 3rd
    EXPECT_EQ(std::tie(p.count, p.shape, p.material, p.area), std::tie(q.count, q.shape, q.material, q.area)) << j;
    EXPECT_EQ(std::memcmp(&p.normal, &q.normal, sizeof(Vec3)) | std::memcmp(&p.centroid, &q.centroid, sizeof(Vec3)), 0);
  }
  EXPECT_EQ(hashPatches(r.mesh), hashPatches(t.mesh));
  // 6 distinct corners (a, b, c, d, e, -0), 3 runs, 17 corner indices: the layout of docs/firstshot-format.md.
  const auto bytes = readBytes(path);
  const size_t p = sectionContents(bytes, "PTCH");
  uint64_t len, counts[3];
  std::memcpy(&len, bytes.data() + p - 8, 8);
  std::memcpy(counts, bytes.data() + p + 16, sizeof(counts));
  EXPECT_EQ(counts[0], 6u);
  EXPECT_EQ(counts[1], 3u);
  EXPECT_EQ(counts[2], 17u);
  EXPECT_EQ(len, 40 + 3 * 12 + 5 + 17 * 4 + 6 * 12 + 5 * (12 + 12 + 8));
}

TEST(FsdFile, MalformedPatchesAreRefused) {
  const std::string dir = test::tempDir();
  writeFirstShot(dir + "/packed.fsd", packedPatchesTable());
  const auto good = readBytes(dir + "/packed.fsd");
  const size_t p = sectionContents(good, "PTCH");
  const size_t runShape = p + 40, runLength = runShape + 2 * 12, corners = runShape + 3 * 12, index = corners + 5;
  const size_t area = index + 17 * 4 + 6 * 12 + 5 * 24;
  auto refused = [&](auto&& change) {
    std::vector<char> m = good;
    change(m);
    writeResealed(dir + "/bad.fsd", m);
    return readError(dir + "/bad.fsd");
  };
  EXPECT_THAT(refused([&](auto& m) { poke<uint32_t>(m, index + 4 * 7, 6); }), HasSubstr("corner index outside the vertex pool"));
  EXPECT_THAT(refused([&](auto& m) { poke<uint8_t>(m, corners + 2, 5); }), HasSubstr("a patch with 5 corners"));
  EXPECT_THAT(refused([&](auto& m) { poke<uint8_t>(m, corners + 2, 4); }), HasSubstr("corner counts do not add up"));
  EXPECT_THAT(refused([&](auto& m) { poke<uint32_t>(m, runLength, 3); }), HasSubstr("runs do not add up"));
  EXPECT_THAT(refused([&](auto& m) { poke<uint32_t>(m, runLength, 0); }), HasSubstr("an empty run"));
  EXPECT_THAT(refused([&](auto& m) { poke<double>(m, area + 8 * 3, 0.0); }), HasSubstr("patch 3 has no positive area"));
  EXPECT_THAT(refused([&](auto& m) { poke<uint32_t>(m, runShape, 7); }), HasSubstr("patches do not match their hash"));
  EXPECT_THAT(refused([&](auto& m) { poke<uint64_t>(m, p + 16, uint64_t(1) << 40); }), HasSubstr("PTCH"));
}
