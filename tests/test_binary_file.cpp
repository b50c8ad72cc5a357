// The binary files' frame (common/util/binary_file.h) on a format of its own: the bytes it writes, and every
// refusal naming the file and the place at fault; then the same refusals through the readers of the
// three formats that use it (.fsd, .fsic, checkpoints).
#include "common/util/binary_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "common/table/firstshot.h"
#include "common/util/error.h"
#include "render/integrators/irradiance_cache/cache_file.h"
#include "render/loop/checkpoint.h"
#include "render/output/film.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

constexpr BinaryFormat kTest{.magic = {"TESTMAGC", 8},
                             .endMarker = {"TESTEND\0", 8},
                             .version = 3,
                             .headerBytes = 16,  // magic, version, one u32
                             .noun = "test file",
                             .identity = "a test file",
                             .remedy = "write it again"};

/// What the round trip writes: a u32, a string, a section of an array, a large array outside sections.
struct Contents {
  uint32_t flags = 7;
  std::string name = "a name";
  std::vector<float> values{1.5f, -2.0f, 3.25f};
  std::vector<uint64_t> large = std::vector<uint64_t>(300000);  // 2.4 MB: streamed in blocks
};

void writeContents(BinaryWriter& o, const Contents& c) {
  o.put(c.flags);
  o.str(c.name);
  o.beginSection("VALS");
  o.put<uint64_t>(c.values.size());
  o.array(c.values);
  o.endSection();
  o.put<uint64_t>(c.large.size());
  o.array(c.large);
}

Contents readContents(const std::string& path) {
  BinaryReader in(path, kTest);
  Contents c;
  c.flags = in.get<uint32_t>("header");
  c.name = in.str("name");
  in.enter("VALS");
  in.array(c.values, in.get<uint64_t>("VALS"), "VALS");
  in.leave("VALS");
  in.array(c.large, in.get<uint64_t>("large"), "large");
  in.expectEnd("large");
  return c;
}

Contents sample() {
  Contents c;
  for (size_t k = 0; k < c.large.size(); ++k) c.large[k] = k * 0x9e3779b97f4a7c15ull;
  return c;
}

/// The error a call throws: its file, element and message.
struct Refusal {
  std::string file, element, message;
};

Refusal refusal(const std::function<void()>& read) {
  try {
    read();
  } catch (const InputError& e) {
    return {e.file(), e.element(), e.what()};
  }
  ADD_FAILURE() << "accepted";
  return {};
}

/// @p bytes with the checksum before the end marker recomputed (a change that only the contents' checks see).
std::string resealed(std::string bytes) {
  const uint64_t h = binaryChecksum(bytes.data(), bytes.size() - 16);
  std::memcpy(bytes.data() + bytes.size() - 16, &h, 8);
  return bytes;
}

class BinaryFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::tempDir();
    good_ = dir_ + "/good.bin";
    writeBinaryFile(good_, kTest, [](BinaryWriter& o) { writeContents(o, sample()); });
    bytes_ = test::readFile(good_);
  }
  /// @p bytes written as a file of this test; @return its path.
  std::string file(const std::string& name, const std::string& bytes) const {
    test::writeText(dir_ + "/" + name, bytes);
    return dir_ + "/" + name;
  }
  Refusal read(const std::string& path) const {
    return refusal([&] { readContents(path); });
  }
  std::string dir_, good_, bytes_;
};

TEST_F(BinaryFile, RoundTripAndLayout) {
  const Contents c = readContents(good_);
  const Contents s = sample();
  EXPECT_EQ(c.flags, s.flags);
  EXPECT_EQ(c.name, s.name);
  EXPECT_EQ(c.values, s.values);
  EXPECT_EQ(c.large, s.large);
  // magic, version 3, flags 7, name, "VALS" + length 8 + 3 × 4, count, array, checksum, end marker.
  const size_t sectionAt = 16 + 4 + s.name.size();
  ASSERT_EQ(bytes_.size(), sectionAt + 12 + 8 + 12 + 8 + 8 * s.large.size() + 16);
  EXPECT_EQ(bytes_.substr(0, 8), "TESTMAGC");
  uint32_t version = 0;
  std::memcpy(&version, bytes_.data() + 8, 4);
  EXPECT_EQ(version, 3u);
  EXPECT_EQ(bytes_.substr(sectionAt, 4), "VALS");
  uint64_t length = 0;
  std::memcpy(&length, bytes_.data() + sectionAt + 4, 8);
  EXPECT_EQ(length, 8u + 12u);
  uint64_t checksum = 0;
  std::memcpy(&checksum, bytes_.data() + bytes_.size() - 16, 8);
  EXPECT_EQ(checksum, Hasher().bytes(bytes_.data(), bytes_.size() - 16).value());
  EXPECT_EQ(bytes_.substr(bytes_.size() - 8), std::string("TESTEND\0", 8));
  // Rewritten from what was read: the same bytes, and no temporary file left beside it.
  writeBinaryFile(dir_ + "/again.bin", kTest, [&](BinaryWriter& o) { writeContents(o, c); });
  EXPECT_EQ(test::readFile(dir_ + "/again.bin"), bytes_);
  for (const auto& e : std::filesystem::directory_iterator(dir_))
    EXPECT_NE(e.path().filename().string().front(), '.') << e.path();
}

TEST_F(BinaryFile, TruncatedFileNamesTheTrailerOrTheHeader) {
  for (const size_t keep : {bytes_.size() - 1, bytes_.size() / 2, size_t(40), size_t(12)}) {
    const std::string path = file("cut.bin", bytes_.substr(0, keep));
    const Refusal r = read(path);
    EXPECT_EQ(r.file, path) << keep;
    EXPECT_EQ(r.element, "trailer") << keep;
    EXPECT_THAT(r.message, HasSubstr("truncated test file (end marker missing)")) << keep;
  }
  const std::string path = file("cut.bin", bytes_.substr(0, 10));  // inside the version
  const Refusal r = read(path);
  EXPECT_EQ(r.element, "header");
  EXPECT_THAT(r.message, HasSubstr("truncated test file (10 bytes, shorter than its header)"));
  // A header and a trailer with nothing between them: shorter than the fixed header.
  EXPECT_EQ(read(file("short.bin", resealed(bytes_.substr(0, 12) + bytes_.substr(bytes_.size() - 16)))).element,
            "trailer");
}

TEST_F(BinaryFile, WrongMagic) {
  std::string b = bytes_;
  b[3] = 'X';
  const std::string path = file("magic.bin", b);
  const Refusal r = read(path);
  EXPECT_EQ(r.file, path);
  EXPECT_EQ(r.element, "header");
  EXPECT_EQ(r.message, path + ": header: not a test file (wrong magic)");
  EXPECT_EQ(read(file("empty.bin", "")).element, "header");
}

TEST_F(BinaryFile, WrongVersionIsNamedBeforeTheTrailerIsChecked) {
  std::string b = bytes_.substr(0, 100);  // another version's layout may differ: its trailer is not looked for
  b[8] = 9;
  const std::string path = file("version.bin", b);
  const Refusal r = read(path);
  EXPECT_EQ(r.file, path);
  EXPECT_EQ(r.element, "header");
  EXPECT_EQ(r.message, path + ": header: format version 9, this build reads version 3: write it again");
}

TEST_F(BinaryFile, CorruptedChecksum) {
  for (const size_t at : {size_t(20), bytes_.size() / 2, bytes_.size() - 16, bytes_.size() - 9}) {
    std::string b = bytes_;
    b[at] = char(b[at] ^ 0x20);  // a byte of the contents, or of the checksum itself
    const std::string path = file("flipped.bin", b);
    const Refusal r = read(path);
    EXPECT_EQ(r.file, path) << at;
    EXPECT_EQ(r.element, "trailer") << at;
    EXPECT_THAT(r.message, HasSubstr("checksum mismatch, the test file is corrupt: write it again")) << at;
  }
}

TEST_F(BinaryFile, SectionTooLongForTheFile) {
  const size_t sectionAt = 16 + 4 + sample().name.size();
  std::string b = bytes_;
  const uint64_t length = uint64_t(1) << 40;
  std::memcpy(b.data() + sectionAt + 4, &length, 8);
  const std::string path = file("long.bin", resealed(b));
  const Refusal r = read(path);
  EXPECT_EQ(r.file, path);
  EXPECT_EQ(r.element, "VALS");
  EXPECT_THAT(r.message, HasSubstr("section of 1099511627776 bytes at offset " + std::to_string(sectionAt + 12) +
                                   ", only " + std::to_string(bytes_.size() - 16 - sectionAt - 12) +
                                   " bytes left before the trailer"));
}

TEST_F(BinaryFile, SectionContentsAreBoundedByItsLength) {
  const size_t sectionAt = 16 + 4 + sample().name.size();
  std::string b = bytes_;
  uint64_t length = 8 + 8;  // one float short: the count of 3 then reads past the section's end
  std::memcpy(b.data() + sectionAt + 4, &length, 8);
  Refusal r = read(file("short-section.bin", resealed(b)));
  EXPECT_EQ(r.element, "VALS");
  EXPECT_THAT(r.message, HasSubstr("truncated or corrupt: 3 elements of 4 bytes counted at offset " +
                                   std::to_string(sectionAt + 20) + ", 8 bytes left"));
  b = bytes_;
  const uint64_t count = 2;  // one float left unread
  std::memcpy(b.data() + sectionAt + 12, &count, 8);
  r = read(file("unread.bin", resealed(b)));
  EXPECT_EQ(r.element, "VALS");
  EXPECT_THAT(r.message, HasSubstr("section length does not match its contents: 4 bytes not read at offset " +
                                   std::to_string(sectionAt + 28)));
  b = bytes_;
  b[sectionAt] = 'W';
  r = read(file("tag.bin", resealed(b)));
  EXPECT_EQ(r.element, "VALS");
  EXPECT_THAT(r.message,
              HasSubstr("section missing or out of order: found \"WALS\" at offset " + std::to_string(sectionAt)));
}

TEST_F(BinaryFile, CountsLargerThanTheFileAndBytesLeftOverAreRefused) {
  const size_t countAt = 16 + 4 + sample().name.size() + 12 + 8 + 12;
  std::string b = bytes_;
  const uint64_t count = uint64_t(1) << 60;  // refused before anything is allocated
  std::memcpy(b.data() + countAt, &count, 8);
  Refusal r = read(file("count.bin", resealed(b)));
  EXPECT_EQ(r.element, "large");
  EXPECT_THAT(r.message, HasSubstr("truncated or corrupt: 1152921504606846976 elements of 8 bytes counted at offset " +
                                   std::to_string(countAt + 8)));
  b = bytes_;
  b.insert(b.size() - 16, "abc");
  r = read(file("extra.bin", resealed(b)));
  EXPECT_EQ(r.element, "large");
  EXPECT_THAT(r.message,
              HasSubstr("unexpected bytes after the contents: 3 bytes at offset " + std::to_string(bytes_.size() - 16)));
}

// A string's length is checked against the bytes left before its characters are allocated (found by the fuzzer:
// a length of 3 GB asked for 3 GB).
TEST_F(BinaryFile, AStringLongerThanTheFileIsRefusedBeforeItIsAllocated) {
  const size_t lengthAt = 12 + 4;  // after the magic, the version and the flags
  std::string b = bytes_;
  const uint32_t length = 0xC0000000u;
  std::memcpy(b.data() + lengthAt, &length, 4);
  const Refusal r = read(file("string.bin", resealed(b)));
  EXPECT_EQ(r.element, "name");
  EXPECT_THAT(r.message, HasSubstr("truncated or corrupt: a string of 3221225472 bytes at offset " + std::to_string(lengthAt + 4)));
}

TEST_F(BinaryFile, MissingFile) {
  const Refusal r = read(dir_ + "/none.bin");
  EXPECT_EQ(r.file, dir_ + "/none.bin");
  EXPECT_EQ(r.element, "");
  EXPECT_THAT(r.message, HasSubstr("cannot open the test file (No such file or directory): write it again"));
}

TEST_F(BinaryFile, FailedWriteLeavesTheTargetAlone) {
  EXPECT_THROW(writeBinaryFile(good_, kTest,
                               [](BinaryWriter& o) {
                                 o.put<uint32_t>(1);
                                 throw std::runtime_error("stopped");
                               }),
               std::runtime_error);
  EXPECT_EQ(test::readFile(good_), bytes_);
  for (const auto& e : std::filesystem::directory_iterator(dir_))
    EXPECT_NE(e.path().filename().string().front(), '.') << "a temporary file left: " << e.path();
  EXPECT_THROW(writeBinaryFile(dir_ + "/nested.bin", kTest,
                               [](BinaryWriter& o) {
                                 o.beginSection("AAAA");
                                 o.beginSection("BBBB");
                               }),
               std::logic_error);
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/nested.bin"));
}

// The three formats' readers refuse through the frame: each error names the file and the place.

/// One format: a good file's bytes, and how to read a file of it.
struct Format {
  std::string name;
  std::function<std::string(const std::string& dir)> good;  ///< writes a good file, returns its path
  std::function<void(const std::string& path)> read;
};

std::vector<Format> formats() {
  return {
      {"fsd", [](const std::string&) { return test::source("tests/fuzz/corpus/fsd/point.fsd"); },
       [](const std::string& p) { readFirstShot(p); }},
      {"fsic", [](const std::string&) { return test::source("tests/fuzz/corpus/cache_file/point.fsic"); },
       [](const std::string& p) {
         // The scene hash and settings the file names, so that a good file is read to its end.
         const std::string b = test::readFile(p);
         uint64_t scene = 0;
         uint32_t n = 0;
         if (b.size() >= 36) std::memcpy(&scene, b.data() + 16, 8), std::memcpy(&n, b.data() + 32, 4);
         readCacheFile(p, scene, b.size() >= 36 + n ? b.substr(36, n) : "");
       }},
      {"checkpoint",
       [](const std::string& dir) {
         Film film(3, 2);
         film.add(1, 1, Color(0.5f), Color(0.2f), Vec3(0, 0, 1));
         writeCheckpoint(dir + "/good.checkpoint", {{"seed", "1"}}, film);
         return dir + "/good.checkpoint";
       },
       [](const std::string& p) {
         Film film(3, 2);
         readCheckpoint(p, {{"seed", "1"}}, film);
       }},
  };
}

class FormatFrame : public ::testing::TestWithParam<Format> {};

TEST_P(FormatFrame, RefusesTruncatedForeignOtherVersionAndCorruptFiles) {
  const Format& f = GetParam();
  const std::string dir = test::tempDir(), good = f.good(dir), bytes = test::readFile(good);
  ASSERT_NO_THROW(f.read(good));
  auto refused = [&](const std::string& name, const std::string& b) {
    const std::string path = dir + "/" + name;
    test::writeText(path, b);
    const Refusal r = refusal([&] { f.read(path); });
    EXPECT_EQ(r.file, path) << name;
    return r;
  };
  Refusal r = refused("cut", bytes.substr(0, bytes.size() - 5));
  EXPECT_EQ(r.element, "trailer");
  EXPECT_THAT(r.message, HasSubstr("truncated"));
  r = refused("foreign", "NOTMAGIC" + bytes.substr(8));
  EXPECT_EQ(r.element, "header");
  EXPECT_THAT(r.message, HasSubstr("wrong magic"));
  std::string b = bytes;
  b[8] = 99;
  r = refused("version", b);
  EXPECT_EQ(r.element, "header");
  EXPECT_THAT(r.message, HasSubstr("format version 99, this build reads version"));
  b = bytes;
  b[b.size() / 2] ^= 4;
  r = refused("flipped", b);
  EXPECT_EQ(r.element, "trailer");
  EXPECT_THAT(r.message, HasSubstr("checksum mismatch"));
  b = bytes;
  b.insert(b.size() - 16, "abcd");
  r = refused("extra", resealed(b));  // the checkpoint's sums are sized by its header
  EXPECT_THAT(r.message, ::testing::AnyOf(HasSubstr("unexpected bytes after the contents: 4 bytes"),
                                          HasSubstr("bytes of sums at offset")));
}

INSTANTIATE_TEST_SUITE_P(ThreeFormats, FormatFrame, ::testing::ValuesIn(formats()),
                         [](const ::testing::TestParamInfo<Format>& i) { return i.param.name; });

TEST(FsdSections, ASectionTooLongForTheFileIsNamed) {
  const std::string bytes = test::readFile(test::source("tests/fuzz/corpus/fsd/point.fsd"));
  const size_t lsmp = bytes.find("LSMP");
  ASSERT_NE(lsmp, std::string::npos);
  std::string b = bytes;
  const uint64_t length = bytes.size();
  std::memcpy(b.data() + lsmp + 4, &length, 8);
  const std::string path = test::tempDir() + "/long.fsd";
  test::writeText(path, resealed(b));
  const Refusal r = refusal([&] { readFirstShot(path); });
  EXPECT_EQ(r.file, path);
  EXPECT_EQ(r.element, "LSMP");
  EXPECT_THAT(r.message,
              HasSubstr("section of " + std::to_string(length) + " bytes at offset " + std::to_string(lsmp + 12)));
}

}  // namespace
