#pragma once
/// @file cache_file.h
/// The irradiance cache file (.fsic): records written by one run and reused by later ones
/// (Ward 1988, end of §3.3). Little-endian binary:
///   "FSICACHE", u32 version (1), u32 flags (0), u64 scene hash (hashScene), u64 settings hash,
///   u32 length + settings text (IrradianceCacheIntegrator::settingsText, for messages),
///   u32 level count; per level: u64 record count, then per record 30 f32:
///     p[3] n[3] E[3] R Rmin Rmax gradT[c][3] (c = 0..2) gradR[c][3] (c = 0..2),
///   u64 checksum (common/util/hash.h Hasher over every byte before it), "FSICEND\0"
///   (the frame of common/util/binary_file.h: header, checksum trailer, atomic write, checked reads).
/// A file is used only if it is whole, intact, and made for the same scene and settings; anything
/// else is refused with an InputError naming the file (exit code 2), never partly used.
#include <cstdint>
#include <string>
#include <vector>

#include "render/integrators/irradiance_cache/cache.h"

namespace firstshot {

struct CacheFileData {
  uint64_t sceneHash = 0;
  std::string settings;  ///< the text the settings hash is computed from
  std::vector<std::vector<IrradianceRecord>> levels;
};

/// Writes @p data atomically (temporary file, then rename). @throws std::runtime_error on I/O failure.
void writeCacheFile(const std::string& path, const CacheFileData& data);

/// Reads and checks a cache file: magic, version, size, checksum, then scene hash and settings
/// against @p sceneHash and @p settings. @throws InputError naming @p path and what is wrong.
CacheFileData readCacheFile(const std::string& path, uint64_t sceneHash, const std::string& settings);

}  // namespace firstshot
