// Render checkpoints: writer and verifying reader.
#include "render/loop/checkpoint.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "common/util/binary_file.h"
#include "common/util/error.h"
#include "common/util/hash.h"

namespace firstshot {

namespace {

constexpr BinaryFormat kFormat{.magic = {"FSRESUME", 8},
                               .endMarker = {"FSCKEND\0", 8},
                               .version = 1,
                               .headerBytes = 8 + 5 * 4,  // magic, version, width, height, key length, passes
                               .noun = "checkpoint file",
                               .identity = "a firstshot-render checkpoint",
                               .remedy = "render with --checkpoint first"};
constexpr size_t kBytesPerPixel = 4 * 3 * sizeof(double) + sizeof(uint32_t);

std::string keyText(const CheckpointKey& key) {
  std::string s;
  for (const auto& [name, value] : key) s += name + "=" + value + "\n";
  return s;
}

CheckpointKey parseKey(const std::string& text) {
  CheckpointKey key;
  size_t pos = 0;
  while (pos < text.size()) {
    const size_t nl = std::min(text.find('\n', pos), text.size());
    const std::string line = text.substr(pos, nl - pos);
    const size_t eq = line.find('=');
    key.emplace_back(line.substr(0, eq), eq == std::string::npos ? "" : line.substr(eq + 1));
    pos = nl + 1;
  }
  return key;
}

/// What differs between the checkpoint's key and this run's, in words ("" if nothing).
std::string keyDifference(const CheckpointKey& saved, const CheckpointKey& now) {
  std::string diff;
  auto find = [](const CheckpointKey& k, const std::string& name) -> const std::string* {
    for (const auto& e : k)
      if (e.first == name) return &e.second;
    return nullptr;
  };
  auto note = [&](const std::string& name, const std::string* was, const std::string* is) {
    diff += fmt::format("{}{} is {} in the checkpoint but {} now", diff.empty() ? "" : "; ", name,
                        was ? "\"" + *was + "\"" : "not set", is ? "\"" + *is + "\"" : "not set");
  };
  for (const auto& [name, value] : now) {
    const std::string* was = find(saved, name);
    if (!was || *was != value) note(name, was, &value);
  }
  for (const auto& [name, value] : saved)
    if (!find(now, name)) note(name, &value, nullptr);
  return diff;
}

}  // namespace

void writeCheckpoint(const std::string& path, const CheckpointKey& key, const Film& film) {
  const Film::Sums& s = film.sums();
  const uint32_t passes = s.count.empty() ? 0 : *std::min_element(s.count.begin(), s.count.end());
  writeBinaryFile(
      path, kFormat,
      [&](BinaryWriter& o) {
        o.put(uint32_t(film.width()));
        o.put(uint32_t(film.height()));
        o.str(keyText(key));
        o.put(passes);
        for (const std::vector<Vec3d>* v : {&s.sum, &s.sumSq, &s.albedo, &s.normal}) o.array(*v);
        o.array(s.count);
      },
      OnInterrupt::Keep);
}

namespace {

/// A checkpoint file, its frame checked (common/util/binary_file.h), read up to its key.
struct CheckpointReader {
  BinaryReader in;
  uint32_t width = 0, height = 0;
  std::string keyText;

  explicit CheckpointReader(const std::string& path) : in(path, kFormat) {
    width = in.get<uint32_t>("header");
    height = in.get<uint32_t>("header");
    keyText = in.str("key");
  }
};

}  // namespace

CheckpointKey readCheckpointKey(const std::string& path) { return parseKey(CheckpointReader(path).keyText); }

int readCheckpoint(const std::string& path, const CheckpointKey& key, Film& film) {
  CheckpointReader r(path);
  BinaryReader& in = r.in;
  const uint32_t width = r.width, height = r.height;
  if (const std::string diff = keyDifference(parseKey(r.keyText), key); !diff.empty())
    throw InputError(path, "key", "made for a different render: " + diff);
  if (int(width) != film.width() || int(height) != film.height())
    throw InputError(path, "header", fmt::format("made for a {}x{} image, this render is {}x{}", width, height,
                                                 film.width(), film.height()));
  const uint32_t passes = in.get<uint32_t>("header");
  const size_t n = size_t(width) * size_t(height);
  if (in.remaining() != n * kBytesPerPixel)
    in.fail("sums", fmt::format("truncated or corrupt: {} bytes of sums at offset {}, a {}x{} image has {}",
                                in.remaining(), in.offset(), width, height, n * kBytesPerPixel));
  Film::Sums s;
  for (std::vector<Vec3d>* v : {&s.sum, &s.sumSq, &s.albedo, &s.normal}) in.array(*v, n, "sums");
  in.array(s.count, n, "sums");
  for (size_t k = 0; k < n; ++k)
    if (s.count[k] < passes)
      in.fail("sums", fmt::format("pixel {}: {} samples, fewer than the {} passes of the header (corrupt file)", k,
                                  s.count[k], passes));
  film.setSums(std::move(s));
  return int(passes);
}

std::string fileContentHash(const std::string& path) {
  std::error_code ec;
  if (path.empty() || !std::filesystem::is_regular_file(path, ec)) return "none";
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "", "cannot read the file");
  Hasher h;
  std::vector<char> buf(1 << 20);
  while (f) {
    f.read(buf.data(), std::streamsize(buf.size()));
    h.bytes(buf.data(), size_t(f.gcount()));
  }
  return fmt::format("{:016x}", h.value());
}

}  // namespace firstshot
