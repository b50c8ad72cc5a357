#pragma once
/// @file gltf_file.h
/// What firstshot reads of a glTF asset (.gltf or .glb) itself, beside assimp: its JSON (for what assimp 5.2 loses),
/// its buffers (checked before assimp reads them, so a missing or unfetched .bin is named as such) and the encoded
/// bytes of its images (common/materials/texture_image.h decodes them).
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace firstshot {

/// Whether @p head, the first bytes of a file, is a Git LFS pointer ("version https://git-lfs.github.com/spec/v1").
bool isGitLfsPointer(std::string_view head);

/// @p j[key] when @p j is an object holding it, else nullptr.
const nlohmann::json* jsonMember(const nlohmann::json& j, const char* key);

/// Element @p k of the array @p gltf[array] (e.g. "textures"), or nullptr.
const nlohmann::json* jsonArrayElement(const nlohmann::json& gltf, const char* array, uint64_t k);

/// assimp 5.2's glTF2 importer numbers an asset's meshes and materials in the order it first meets them, not the
/// file's: the default scene's nodes depth first (a node's children before its own mesh), a mesh's primitives in
/// order, then the nodes that skins' joints and animations' targets reach. By assimp's index, the file's.
struct GltfAssimpOrder {
  std::vector<uint64_t> meshes, materials;
};
GltfAssimpOrder gltfAssimpOrder(const nlohmann::json& gltf);

/// The end of a message about a file that is a Git LFS pointer.
inline constexpr const char* kGitLfsPointerMessage = "is a Git LFS pointer, not the data: fetch it with git lfs pull";

/// The first bytes of the file at @p path (at most @p n; "" when unreadable).
std::string fileHead(const std::filesystem::path& path, size_t n = 64);

/// A glTF asset's JSON and access to its binary data. Reading never throws: a file whose JSON does not parse
/// leaves json() null and parseError() set; values of the wrong type count as absent.
class GltfFile {
 public:
  explicit GltfFile(const std::string& path);

  const nlohmann::json& json() const { return json_; }
  const std::string& parseError() const { return parseError_; }
  const std::filesystem::path& path() const { return path_; }

  /// What is wrong with the first broken buffer, or "": "buffer file F is missing", "buffer file F is a Git LFS
  /// pointer, …", "buffer file F has N bytes, the glTF says M" (likewise for a data URI or a .glb's binary chunk).
  std::string bufferDefect() const;

  /// The encoded bytes of images[@p k]: a data URI, a file beside the asset, or a bufferView.
  /// @throws InputError (no file or element; the caller adds them) saying what is missing or broken.
  std::string imageBytes(size_t k) const;

 private:
  /// Where buffers[k]'s bytes are: a data URI's text, a file, or the .glb's binary chunk. "" in @p defect if sound.
  struct BufferSource {
    std::string dataUri;           ///< the URI when it is a data URI
    std::filesystem::path file;    ///< the file when it is one (else empty)
    bool glbChunk = false;         ///< the .glb's binary chunk
    uint64_t byteLength = 0;       ///< what the glTF says
    std::string name;              ///< for messages: "buffer file F", "buffers[k] (data URI)", "the .glb's binary chunk"
  };
  BufferSource bufferSource(size_t k, std::string& defect) const;
  /// All bytes of buffers[@p k] (cached). @throws InputError as imageBytes.
  const std::string& bufferBytes(size_t k) const;

  std::filesystem::path path_;
  nlohmann::json json_;
  std::string parseError_;
  uint64_t glbChunkOffset_ = 0, glbChunkSize_ = 0;  ///< the .glb's binary chunk in the file (size 0: none)
  bool glb_ = false;
  mutable std::map<size_t, std::string> buffers_;
};

}  // namespace firstshot
