// Render checkpoints: writer and verifying reader.
#include "render/loop/checkpoint.h"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/hash.h"

namespace fs {

namespace {

constexpr char kMagic[8] = {'F', 'S', 'R', 'E', 'S', 'U', 'M', 'E'};
constexpr char kEnd[8] = {'F', 'S', 'C', 'K', 'E', 'N', 'D', '\0'};
constexpr uint32_t kVersion = 1;
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
  static_assert(std::endian::native == std::endian::little, "the checkpoint file is little-endian");
  const Film::Sums& s = film.sums();
  const std::string text = keyText(key);
  const uint32_t passes = s.count.empty() ? 0 : *std::min_element(s.count.begin(), s.count.end());
  writeAtomically(
      path,
      [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) throw std::runtime_error(path + ": cannot create file");
        Hasher h;
        auto put = [&](const void* data, size_t n) {
          h.bytes(data, n);
          f.write(static_cast<const char*>(data), std::streamsize(n));
        };
        auto put32 = [&](uint32_t v) { put(&v, sizeof v); };
        put(kMagic, 8);
        put32(kVersion);
        put32(uint32_t(film.width()));
        put32(uint32_t(film.height()));
        put32(uint32_t(text.size()));
        put(text.data(), text.size());
        put32(passes);
        for (const std::vector<Vec3d>* v : {&s.sum, &s.sumSq, &s.albedo, &s.normal}) put(v->data(), v->size() * sizeof(Vec3d));
        put(s.count.data(), s.count.size() * sizeof(uint32_t));
        const uint64_t checksum = h.value();
        f.write(reinterpret_cast<const char*>(&checksum), sizeof checksum);
        f.write(kEnd, 8);
        f.close();
        if (!f) throw std::runtime_error(path + ": write failed (disk full?)");
      },
      OnInterrupt::Keep);
}

namespace {

/// A checkpoint file's bytes, checked (magic, end marker, checksum, version), read up to its key.
struct CheckpointReader {
  std::string path;
  std::vector<char> data;
  size_t pos = 0;
  uint32_t width = 0, height = 0;
  std::string keyText;

  explicit CheckpointReader(const std::string& p) : path(p) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "", "cannot open the checkpoint file (render with --checkpoint first)");
    data.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    if (data.size() < 8 || std::memcmp(data.data(), kMagic, 8) != 0)
      throw InputError(path, "header", "not a firstshot-render checkpoint (wrong magic)");
    if (data.size() < 8 + 5 * 4 + 16 || std::memcmp(data.data() + data.size() - 8, kEnd, 8) != 0)
      throw InputError(path, "trailer", "truncated checkpoint file (end marker missing)");
    uint64_t stored;
    std::memcpy(&stored, data.data() + data.size() - 16, 8);
    if (Hasher().bytes(data.data(), data.size() - 16).value() != stored)
      throw InputError(path, "trailer", "checksum mismatch: the checkpoint is corrupt");
    pos = 8;
    const uint32_t version = get32("header");
    if (version != kVersion)
      throw InputError(path, "header", fmt::format("checkpoint version {}, this build reads version {}", version, kVersion));
    width = get32("header");
    height = get32("header");
    keyText.resize(get32("key"));
    get(keyText.data(), keyText.size(), "key");
  }
  void get(void* out, size_t n, const char* what) {
    if (n > data.size() - 16 - pos) throw InputError(path, what, "truncated checkpoint file");
    std::memcpy(out, data.data() + pos, n);
    pos += n;
  }
  uint32_t get32(const char* what) {
    uint32_t v;
    get(&v, sizeof v, what);
    return v;
  }
};

}  // namespace

CheckpointKey readCheckpointKey(const std::string& path) { return parseKey(CheckpointReader(path).keyText); }

int readCheckpoint(const std::string& path, const CheckpointKey& key, Film& film) {
  CheckpointReader in(path);
  const uint32_t width = in.width, height = in.height;
  if (const std::string diff = keyDifference(parseKey(in.keyText), key); !diff.empty())
    throw InputError(path, "key", "made for a different render: " + diff);
  if (int(width) != film.width() || int(height) != film.height())
    throw InputError(path, "header", fmt::format("made for a {}x{} image, this render is {}x{}", width, height,
                                                 film.width(), film.height()));
  const uint32_t passes = in.get32("header");
  const size_t n = size_t(width) * size_t(height);
  if (in.data.size() - 16 - in.pos != n * kBytesPerPixel) throw InputError(path, "sums", "truncated or corrupt: wrong size");
  Film::Sums s;
  for (std::vector<Vec3d>* v : {&s.sum, &s.sumSq, &s.albedo, &s.normal}) {
    v->resize(n);
    in.get(v->data(), n * sizeof(Vec3d), "sums");
  }
  s.count.resize(n);
  in.get(s.count.data(), n * sizeof(uint32_t), "sums");
  for (const uint32_t c : s.count)
    if (c < passes) throw InputError(path, "sums", "inconsistent sample counts (corrupt file)");
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

}  // namespace fs
