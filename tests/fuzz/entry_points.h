#pragma once
/// @file entry_points.h
/// What each fuzz target does with one input: the same loading calls the tools make, on bytes
/// instead of a named file. Shared by the libFuzzer targets (fuzz_*.cpp, FIRSTSHOT_FUZZ build) and
/// the regression test that replays saved crash inputs (tests/test_fuzz_regressions.cpp).
/// Each function either returns or throws firstshot::InputError, the documented outcome for bad input;
/// anything else (a crash, a sanitizer report, another exception, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace firstshot::fuzz {

/// A JSON scene as firstshot-preprocess/-render load it (loadScene): parseSceneJson, validateScene,
/// hashScene. The scene "file" sits in the source tree's scenes/ folder, so the shipped scenes'
/// relative mesh files resolve.
void sceneJson(std::string_view bytes);

/// A Mitsuba 3 XML scene as the tools load it: parseSceneMitsuba, validateScene, hashScene; the scene "file" sits
/// in scenes/ as for sceneJson.
void sceneXml(std::string_view bytes);

/// A mesh or asset file through assimp: loadScene's importAssetScene + validateScene, and
/// loadMeshFile (a JSON scene's "mesh" shape). The extension comes from the content: "glTF" → .glb,
/// "ply" → .ply, a leading '{' → .gltf, else .obj.
void meshImport(std::string_view bytes);

/// A first-shot table (.fsd) through readFirstShot. When the bytes end with the end marker, the
/// checksum before it is recomputed first, so that mutations reach the sections behind it.
void firstShotFile(std::string_view bytes);

/// An irradiance cache file (.fsic) through readCacheFile, with the checksum recomputed as above and
/// the scene hash and settings text the file itself names, so that the records are parsed.
void cacheFile(std::string_view bytes);

/// An IES LM-63 photometric file through parseIes, then its table evaluated, integrated and sampled
/// in a few directions (common/lights/ies.h).
void iesFile(std::string_view bytes);

/// The target of each name ("scene_json", "scene_xml", "mesh_import", "fsd", "cache_file", "ies"), or nullptr.
using EntryPoint = void (*)(std::string_view);
EntryPoint entryPoint(std::string_view target);

/// One libFuzzer input through @p f, firstshot::InputError being an expected outcome (printed on stderr
/// when the environment variable FIRSTSHOT_FUZZ_VERBOSE is set). @return 0 (libFuzzer's "keep going").
int runOne(EntryPoint f, const uint8_t* data, size_t size);

}  // namespace firstshot::fuzz
