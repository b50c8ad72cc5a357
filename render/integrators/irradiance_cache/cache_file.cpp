// The irradiance cache file: writer and verifying reader.
#include "render/integrators/irradiance_cache/cache_file.h"

#include <sstream>

#include "common/util/binary_file.h"
#include "common/util/hash.h"

namespace firstshot {

namespace {

constexpr BinaryFormat kFormat{.magic = {"FSICACHE", 8},
                               .endMarker = {"FSICEND\0", 8},
                               .version = 1,
                               .headerBytes = 8 + 4 + 4 + 8 + 8,  // magic, version, flags, scene hash, settings hash
                               .noun = "irradiance cache file",
                               .identity = "an irradiance cache file",
                               .remedy = "delete the file to rebuild the cache"};
constexpr size_t kFloatsPerRecord = 30;

uint64_t settingsHash(const std::string& text) { return Hasher().add(std::string_view(text)).value(); }

}  // namespace

void writeCacheFile(const std::string& path, const CacheFileData& d) {
  writeBinaryFile(path, kFormat, [&](BinaryWriter& o) {
    o.put<uint32_t>(0);  // flags
    o.put(d.sceneHash);
    o.put(settingsHash(d.settings));
    o.str(d.settings);
    o.put<uint32_t>(uint32_t(d.levels.size()));
    for (const auto& level : d.levels) {
      o.put<uint64_t>(level.size());
      for (const IrradianceRecord& r : level) {
        o.put(r.p), o.put(r.n), o.put(r.E), o.put(r.R), o.put(r.Rmin), o.put(r.Rmax);
        for (const Vec3& g : r.gradT) o.put(g);
        for (const Vec3& g : r.gradR) o.put(g);
      }
    }
  });
}

CacheFileData readCacheFile(const std::string& path, uint64_t sceneHash, const std::string& settings) {
  BinaryReader in(path, kFormat);
  CacheFileData d;
  in.get<uint32_t>("header");  // flags
  d.sceneHash = in.get<uint64_t>("header");
  const uint64_t hash = in.get<uint64_t>("header");
  d.settings = in.str("settings");
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
  for (size_t l = 0; l < d.levels.size(); ++l) {
    auto& level = d.levels[l];
    const uint64_t n = in.get<uint64_t>("records");
    if (n > in.remaining() / (kFloatsPerRecord * 4))
      in.fail("records", "level " + std::to_string(l) + ": truncated or corrupt: fewer records than counted");
    level.resize(n);
    for (size_t k = 0; k < level.size(); ++k) {
      IrradianceRecord& r = level[k];
      r.p = in.get<Vec3>("records"), r.n = in.get<Vec3>("records"), r.E = in.get<Color>("records");
      r.R = in.get<float>("records"), r.Rmin = in.get<float>("records"), r.Rmax = in.get<float>("records");
      for (Vec3& g : r.gradT) g = in.get<Vec3>("records");
      for (Vec3& g : r.gradR) g = in.get<Vec3>("records");
      if (!isFinite(r.p) || !isFinite(r.n) || !isFinite(r.E) || !(r.R > 0) || !(r.Rmin >= 0) || !(r.Rmax > 0))
        in.fail("records",
                "level " + std::to_string(l) + ", record " + std::to_string(k) + ": invalid record (corrupt file)");
    }
  }
  in.expectEnd("records");
  return d;
}

}  // namespace firstshot
