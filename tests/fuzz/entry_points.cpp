// The fuzz targets' entry points: bytes → a scratch file → the loaders the tools call.
#include "tests/fuzz/entry_points.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/formats/assets/mesh_import.h"
#include "common/formats/json/scene_json.h"
#include "common/formats/mitsuba/scene_mitsuba.h"
#include "common/lights/ies.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "common/util/error.h"
#include "common/util/hash.h"
#include "render/integrators/irradiance_cache/cache_file.h"

#ifndef FIRSTSHOT_SOURCE_DIR
#error "FIRSTSHOT_SOURCE_DIR must name the source tree"
#endif

namespace firstshot::fuzz {
namespace {

/// A per-process scratch folder (removed at exit) holding one file per name, rewritten for every input.
std::string scratchFile(const std::string& name, std::string_view bytes) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("firstshot-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(std::filesystem::temp_directory_path() / ("firstshot-fuzz-" + std::to_string(getpid())), ec);
    });
    return d;
  }();
  const std::string path = (dir / name).string();
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), std::streamsize(bytes.size()));
  if (!f.flush()) throw std::runtime_error(path + ": cannot write the fuzz input");
  return path;
}

/// @p bytes with the u64 checksum (common/util/hash.h over every byte before it) that precedes the 8-byte
/// end marker recomputed, when the bytes end with @p endMarker; otherwise unchanged.
std::string withChecksum(std::string_view bytes, std::string_view endMarker) {
  std::string s(bytes);
  if (s.size() >= 16 && std::string_view(s).substr(s.size() - 8) == endMarker) {
    const uint64_t h = Hasher().bytes(s.data(), s.size() - 16).value();
    std::memcpy(s.data() + s.size() - 16, &h, 8);
  }
  return s;
}

}  // namespace

void sceneJson(std::string_view bytes) {
  SceneDesc scene = parseSceneJson(std::string(bytes), FIRSTSHOT_SOURCE_DIR "/scenes/fuzz-input.json");
  validateScene(scene);
  hashScene(scene);
}

void sceneXml(std::string_view bytes) {
  SceneDesc scene = parseSceneMitsuba(std::string(bytes), FIRSTSHOT_SOURCE_DIR "/scenes/fuzz-input.xml");
  validateScene(scene);
  hashScene(scene);
}

void meshImport(std::string_view bytes) {
  const char* ext = ".obj";
  if (bytes.substr(0, 4) == "glTF") ext = ".glb";
  else if (bytes.substr(0, 3) == "ply") ext = ".ply";
  else if (const size_t first = bytes.find_first_not_of(" \t\r\n"); first != bytes.npos && bytes[first] == '{') ext = ".gltf";
  const std::string path = scratchFile(std::string("mesh") + ext, bytes);
  SceneDesc scene = importAssetScene(path);
  validateScene(scene);
  loadMeshFile(path, path, "mesh");
}

void firstShotFile(std::string_view bytes) {
  readFirstShot(scratchFile("table.fsd", withChecksum(bytes, std::string_view("FSHOTEND", 8))));
}

void cacheFile(std::string_view bytes) {
  // Header: magic[8], version u32, flags u32, scene hash u64 (offset 16), settings hash u64,
  // settings length u32 (offset 32), settings text (render/integrators/irradiance_cache/cache_file.h).
  uint64_t sceneHash = 0;
  std::string settings;
  if (bytes.size() >= 24) std::memcpy(&sceneHash, bytes.data() + 16, 8);
  if (bytes.size() >= 36) {
    uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 32, 4);
    if (n <= bytes.size() - 36) settings = std::string(bytes.substr(36, n));
  }
  readCacheFile(scratchFile("cache.fsic", withChecksum(bytes, std::string_view("FSICEND\0", 8))), sceneHash, settings);
}

int runOne(EntryPoint f, const uint8_t* data, size_t size) {
  try {
    f(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const InputError& e) {  // the documented outcome for bad input
    static const bool verbose = std::getenv("FIRSTSHOT_FUZZ_VERBOSE") != nullptr;
    if (verbose) std::fprintf(stderr, "InputError: %s\n", e.what());
  }
  return 0;
}

void iesFile(std::string_view bytes) {
  const IesData d = parseIes(std::string(bytes), "fuzz.ies");
  for (int k = 0; k < 16; ++k) {
    double pdf = 0;
    const Vec3d w = d.sampleLocal((k + 0.5) / 16, (k * 7 % 16 + 0.5) / 16, pdf);
    if (!(d.valueLocal(w) >= 0) || !(pdf >= 0) || !(d.pdfLocal(w) >= 0)) throw std::logic_error("bad IES table value");
  }
}

EntryPoint entryPoint(std::string_view target) {
  if (target == "scene_json") return sceneJson;
  if (target == "scene_xml") return sceneXml;
  if (target == "mesh_import") return meshImport;
  if (target == "fsd") return firstShotFile;
  if (target == "cache_file") return cacheFile;
  if (target == "ies") return iesFile;
  return nullptr;
}

}  // namespace firstshot::fuzz
