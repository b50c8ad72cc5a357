// The irradiance cache file: writer and verifying reader.
#include "render/integrators/irradiance_cache/cache_file.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/hash.h"

namespace fs {

namespace {

constexpr char kMagic[8] = {'F', 'S', 'I', 'C', 'A', 'C', 'H', 'E'};
constexpr char kEnd[8] = {'F', 'S', 'I', 'C', 'E', 'N', 'D', '\0'};
constexpr uint32_t kVersion = 1;
constexpr size_t kFloatsPerRecord = 30;
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;  ///< magic, version, flags, scene hash, settings hash

uint64_t settingsHash(const std::string& text) { return Hasher().add(std::string_view(text)).value(); }

template <typename T>
void put(std::vector<char>& buf, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  const size_t at = buf.size();
  buf.resize(at + sizeof(T));
  std::memcpy(buf.data() + at, &v, sizeof(T));
}

/// Bounds-checked reading; every failure names the file and the part at fault.
class Reader {
 public:
  Reader(const std::string& path, const std::vector<char>& data, size_t end) : path_(path), data_(data), end_(end) {}
  template <typename T>
  T get(const char* what) {
    if (sizeof(T) > end_ - pos_) fail(what, "truncated file");
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  size_t remaining() const { return end_ - pos_; }
  std::string str(uint32_t n, const char* what) {
    if (n > remaining()) fail(what, "truncated file");
    std::string s(data_.data() + pos_, n);
    pos_ += n;
    return s;
  }
  [[noreturn]] void fail(const char* what, const std::string& msg) const { throw InputError(path_, what, msg); }

 private:
  const std::string& path_;
  const std::vector<char>& data_;
  size_t pos_ = 0, end_;
};

}  // namespace

void writeCacheFile(const std::string& path, const CacheFileData& d) {
  static_assert(std::endian::native == std::endian::little, "the cache file is little-endian");
  std::vector<char> buf(kMagic, kMagic + 8);
  put(buf, kVersion);
  put<uint32_t>(buf, 0);
  put(buf, d.sceneHash);
  put(buf, settingsHash(d.settings));
  put<uint32_t>(buf, uint32_t(d.settings.size()));
  buf.insert(buf.end(), d.settings.begin(), d.settings.end());
  put<uint32_t>(buf, uint32_t(d.levels.size()));
  for (const auto& level : d.levels) {
    put<uint64_t>(buf, level.size());
    for (const IrradianceRecord& r : level) {
      put(buf, r.p), put(buf, r.n), put(buf, r.E), put(buf, r.R), put(buf, r.Rmin), put(buf, r.Rmax);
      for (const Vec3& g : r.gradT) put(buf, g);
      for (const Vec3& g : r.gradR) put(buf, g);
    }
  }
  put(buf, Hasher().bytes(buf.data(), buf.size()).value());
  buf.insert(buf.end(), kEnd, kEnd + 8);
  writeAtomically(path, [&](const std::string& tmp) {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error(path + ": cannot create file");
    f.write(buf.data(), std::streamsize(buf.size()));
    f.close();
    if (!f) throw std::runtime_error(path + ": write failed (disk full?)");
  });
}

CacheFileData readCacheFile(const std::string& path, uint64_t sceneHash, const std::string& settings) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "", "cannot open irradiance cache file");
  const std::vector<char> data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (data.size() < 8 || std::memcmp(data.data(), kMagic, 8) != 0)
    throw InputError(path, "header", "not an irradiance cache file (wrong magic)");
  if (data.size() < kHeaderBytes + 16 || std::memcmp(data.data() + data.size() - 8, kEnd, 8) != 0)
    throw InputError(path, "trailer", "truncated irradiance cache file (end marker missing)");
  Reader in(path, data, data.size() - 16);
  in.get<uint64_t>("header");
  const uint32_t version = in.get<uint32_t>("header");
  if (version != kVersion)
    in.fail("header", "format version " + std::to_string(version) + ", this build reads version " +
                          std::to_string(kVersion) + ": delete the file to rebuild the cache");
  uint64_t stored;
  std::memcpy(&stored, data.data() + data.size() - 16, 8);
  if (Hasher().bytes(data.data(), data.size() - 16).value() != stored)
    in.fail("trailer", "checksum mismatch: the file is corrupt (delete it to rebuild the cache)");

  CacheFileData d;
  in.get<uint32_t>("header");  // flags
  d.sceneHash = in.get<uint64_t>("header");
  const uint64_t hash = in.get<uint64_t>("header");
  d.settings = in.str(in.get<uint32_t>("settings"), "settings");
  if (settingsHash(d.settings) != hash) in.fail("settings", "settings do not match their hash (corrupt file)");
  if (d.sceneHash != sceneHash) {
    std::ostringstream msg;
    msg << "made for a different scene (scene hash " << std::hex << d.sceneHash << ", this scene " << sceneHash
        << "); use another --cache-file or delete this one";
    in.fail("header", msg.str());
  }
  if (d.settings != settings)
    in.fail("settings", "made with different settings (file: " + d.settings + "; now: " + settings +
                            "); use another --cache-file or the same settings");

  const uint32_t levels = in.get<uint32_t>("records");
  if (levels > 64) in.fail("records", "implausible level count (corrupt file)");
  d.levels.resize(levels);
  for (auto& level : d.levels) {
    const uint64_t n = in.get<uint64_t>("records");
    if (n > in.remaining() / (kFloatsPerRecord * 4)) in.fail("records", "truncated or corrupt: fewer records than counted");
    level.resize(n);
    for (IrradianceRecord& r : level) {
      r.p = in.get<Vec3>("records"), r.n = in.get<Vec3>("records"), r.E = in.get<Color>("records");
      r.R = in.get<float>("records"), r.Rmin = in.get<float>("records"), r.Rmax = in.get<float>("records");
      for (Vec3& g : r.gradT) g = in.get<Vec3>("records");
      for (Vec3& g : r.gradR) g = in.get<Vec3>("records");
      if (!isFinite(r.p) || !isFinite(r.n) || !isFinite(r.E) || !(r.R > 0) || !(r.Rmin >= 0) || !(r.Rmax > 0))
        in.fail("records", "invalid record (corrupt file)");
    }
  }
  if (in.remaining() != 0) in.fail("records", "unexpected bytes after the records (corrupt file)");
  return d;
}

}  // namespace fs
