// A glTF asset's JSON, buffers and image bytes, read beside assimp (common/formats/assets/gltf_file.h).
#include "common/formats/assets/gltf_file.h"

#include <cctype>
#include <cstring>
#include <fstream>
#include <utility>

#include "common/util/error.h"

namespace firstshot {
namespace {

using Json = nlohmann::json;

/// @p j[key] as an unsigned integer, or @p fallback when absent or not one.
uint64_t unsignedMember(const Json& j, const char* key, uint64_t fallback) {
  const Json* v = jsonMember(j, key);
  return v && v->is_number_unsigned() ? v->get<uint64_t>() : fallback;
}

/// The string @p j[key], or "".
std::string stringMember(const Json& j, const char* key) {
  const Json* v = jsonMember(j, key);
  return v && v->is_string() ? v->get<std::string>() : std::string();
}

bool isDataUri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

/// The bytes of a base64 data URI ("data:[type];base64,…"). @throws InputError naming @p name if it is not base64.
std::string decodeDataUri(const std::string& uri, const std::string& name) {
  const size_t comma = uri.find(',');
  if (comma == std::string::npos || comma < 7 || uri.compare(comma - 7, 7, ";base64") != 0)
    throw InputError("", "", name + " is a data URI that is not base64");
  std::string out;
  uint32_t bits = 0;
  int count = 0;
  for (size_t i = comma + 1; i < uri.size() && uri[i] != '='; ++i) {
    const char c = uri[i];
    const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* p = c ? std::strchr(abc, c) : nullptr;
    if (!p) throw InputError("", "", name + " is a data URI with a character outside base64");
    bits = bits << 6 | uint32_t(p - abc);
    if ((count += 6) >= 8) out += char((bits >> (count -= 8)) & 0xff);
  }
  return out;
}

/// A relative URI reference with its %XX escapes decoded.
std::string decodePercent(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

/// The whole file @p path. @throws InputError naming @p name when it is missing or an LFS pointer.
std::string readWhole(const std::filesystem::path& path, const std::string& name) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("", "", name + " is missing");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (isGitLfsPointer(bytes)) throw InputError("", "", name + " " + kGitLfsPointerMessage);
  return bytes;
}

uint32_t u32(const std::string& bytes, size_t at) {
  uint32_t v = 0;
  if (at + 4 <= bytes.size()) std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

}  // namespace

const Json* jsonMember(const Json& j, const char* key) {
  if (!j.is_object()) return nullptr;
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

const Json* jsonArrayElement(const Json& gltf, const char* array, uint64_t k) {
  const Json* a = jsonMember(gltf, array);
  return a && a->is_array() && k < a->size() ? &(*a)[size_t(k)] : nullptr;
}

bool isGitLfsPointer(std::string_view head) { return head.rfind("version https://git-lfs.github.com/spec/v1", 0) == 0; }

std::string fileHead(const std::filesystem::path& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string head(n, '\0');
  in.read(head.data(), std::streamsize(n));
  head.resize(size_t(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

GltfFile::GltfFile(const std::string& path) : path_(path) {
  std::ifstream in(path, std::ios::binary);
  std::string text = fileHead(path, 20);
  if (text.size() == 20 && text.compare(0, 4, "glTF") == 0) {  // GLB: 12-byte header, the JSON chunk, the BIN chunk
    glb_ = true;
    std::error_code ec;
    const uint64_t fileSize = std::filesystem::file_size(path, ec);
    const uint64_t jsonLength = std::min<uint64_t>(u32(text, 12), fileSize > 20 ? fileSize - 20 : 0);
    text.assign(jsonLength, '\0');
    in.seekg(20);
    in.read(text.data(), std::streamsize(jsonLength));
    std::string chunk(8, '\0');
    const uint64_t chunkAt = 20 + (jsonLength + 3) / 4 * 4;
    in.seekg(std::streamoff(chunkAt));
    if (in.read(chunk.data(), 8) && chunk.compare(4, 3, "BIN") == 0) {
      glbChunkOffset_ = chunkAt + 8;
      glbChunkSize_ = std::min<uint64_t>(u32(chunk, 0), fileSize - std::min(fileSize, glbChunkOffset_));
    }
  } else {
    text.assign((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  try {
    json_ = Json::parse(text);
  } catch (const Json::exception& e) {
    parseError_ = e.what();
    json_ = nullptr;
  }
}

GltfFile::BufferSource GltfFile::bufferSource(size_t k, std::string& defect) const {
  BufferSource s;
  const std::string where = "buffers[" + std::to_string(k) + "]";
  const Json* buffer = jsonArrayElement(json_, "buffers", k);
  if (!buffer) {
    defect = where + " does not exist";
    return s;
  }
  s.byteLength = unsignedMember(*buffer, "byteLength", 0);
  const std::string uri = stringMember(*buffer, "uri");
  if (uri.empty()) {
    s.glbChunk = glb_ && k == 0;
    s.name = s.glbChunk ? "the .glb's binary chunk" : where;
    if (!s.glbChunk) defect = where + " has no uri";
    else if (glbChunkSize_ < s.byteLength)
      defect = s.name + " has " + std::to_string(glbChunkSize_) + " bytes, the glTF says " + std::to_string(s.byteLength);
    return s;
  }
  if (isDataUri(uri)) {
    s.dataUri = uri;
    s.name = where + " (data URI)";
    return s;  // its length is checked once decoded (bufferBytes)
  }
  s.file = path_.parent_path() / decodePercent(uri);
  s.name = "buffer file " + s.file.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(s.file, ec)) {
    defect = s.name + " is missing";
  } else if (isGitLfsPointer(fileHead(s.file))) {
    defect = s.name + " " + kGitLfsPointerMessage;
  } else if (const uint64_t size = std::filesystem::file_size(s.file, ec); size < s.byteLength) {
    defect = s.name + " has " + std::to_string(size) + " bytes, the glTF says " + std::to_string(s.byteLength);
  }
  return s;
}

std::string GltfFile::bufferDefect() const {
  const Json* buffers = jsonMember(json_, "buffers");
  for (size_t k = 0; buffers && buffers->is_array() && k < buffers->size(); ++k) {
    std::string defect;
    const BufferSource s = bufferSource(k, defect);
    if (defect.empty() && !s.dataUri.empty()) {
      try {
        bufferBytes(k);
      } catch (const InputError& e) {
        defect = e.what();
      }
    }
    if (!defect.empty()) return defect;
  }
  return "";
}

const std::string& GltfFile::bufferBytes(size_t k) const {
  if (const auto it = buffers_.find(k); it != buffers_.end()) return it->second;
  std::string defect;
  const BufferSource s = bufferSource(k, defect);
  if (!defect.empty()) throw InputError("", "", defect);
  std::string bytes;
  if (s.glbChunk) {
    std::ifstream in(path_, std::ios::binary);
    bytes.assign(glbChunkSize_, '\0');
    in.seekg(std::streamoff(glbChunkOffset_));
    in.read(bytes.data(), std::streamsize(glbChunkSize_));
  } else if (!s.dataUri.empty()) {
    bytes = decodeDataUri(s.dataUri, s.name);
    if (bytes.size() < s.byteLength)
      throw InputError("", "", s.name + " has " + std::to_string(bytes.size()) + " bytes, the glTF says " +
                                   std::to_string(s.byteLength));
  } else {
    bytes = readWhole(s.file, s.name);
  }
  return buffers_[k] = std::move(bytes);
}

std::string GltfFile::imageBytes(size_t k) const {
  const Json* image = jsonArrayElement(json_, "images", k);
  const std::string where = "images[" + std::to_string(k) + "]";
  if (!image) throw InputError("", "", where + " does not exist");
  const std::string uri = stringMember(*image, "uri");
  if (isDataUri(uri)) return decodeDataUri(uri, where);
  if (!uri.empty()) {
    const std::filesystem::path file = path_.parent_path() / decodePercent(uri);
    return readWhole(file, "image file " + file.string());
  }
  const uint64_t view = unsignedMember(*image, "bufferView", UINT64_MAX);
  const Json* bufferView = jsonArrayElement(json_, "bufferViews", view);
  if (!bufferView) throw InputError("", "", where + " has neither a uri nor a bufferView");
  const std::string& buffer = bufferBytes(unsignedMember(*bufferView, "buffer", UINT64_MAX));
  const uint64_t offset = unsignedMember(*bufferView, "byteOffset", 0), length = unsignedMember(*bufferView, "byteLength", 0);
  if (offset > buffer.size() || length > buffer.size() - offset)
    throw InputError("", "", where + "'s bufferView lies outside its buffer");
  return buffer.substr(offset, length);
}

GltfAssimpOrder gltfAssimpOrder(const nlohmann::json& gltf) {
  GltfAssimpOrder order;
  std::vector<uint8_t> nodeSeen, meshSeen, materialSeen;
  const auto first = [](std::vector<uint8_t>& seen, uint64_t k) {  // true the first time k is met
    if (seen.size() <= k) seen.resize(k + 1, 0);
    return !std::exchange(seen[k], uint8_t(1));
  };
  const auto index = [](const nlohmann::json* j, uint64_t& k) {
    if (!j || !j->is_number_unsigned()) return false;
    k = j->get<uint64_t>();
    return true;
  };
  const auto visitMesh = [&](uint64_t m) {
    const nlohmann::json* mesh = jsonArrayElement(gltf, "meshes", m);
    if (!mesh || !first(meshSeen, m)) return;
    order.meshes.push_back(m);
    const nlohmann::json* prims = jsonMember(*mesh, "primitives");
    if (!prims || !prims->is_array()) return;
    for (const nlohmann::json& p : *prims)
      if (uint64_t k = 0; index(jsonMember(p, "material"), k) && jsonArrayElement(gltf, "materials", k) && first(materialSeen, k))
        order.materials.push_back(k);
  };
  const auto visitNode = [&](auto&& self, uint64_t n, int depth) -> void {
    const nlohmann::json* node = jsonArrayElement(gltf, "nodes", n);
    if (!node || depth > 256 || !first(nodeSeen, n)) return;
    if (const nlohmann::json* children = jsonMember(*node, "children"); children && children->is_array())
      for (const nlohmann::json& c : *children)
        if (uint64_t k = 0; index(&c, k)) self(self, k, depth + 1);
    if (uint64_t m = 0; index(jsonMember(*node, "mesh"), m)) visitMesh(m);
  };
  uint64_t scene = 0;
  index(jsonMember(gltf, "scene"), scene);
  if (const nlohmann::json* s = jsonArrayElement(gltf, "scenes", scene))
    if (const nlohmann::json* nodes = jsonMember(*s, "nodes"); nodes && nodes->is_array())
      for (const nlohmann::json& n : *nodes)
        if (uint64_t k = 0; index(&n, k)) visitNode(visitNode, k, 0);
  if (const nlohmann::json* skins = jsonMember(gltf, "skins"); skins && skins->is_array())
    for (const nlohmann::json& skin : *skins)
      if (const nlohmann::json* joints = jsonMember(skin, "joints"); joints && joints->is_array())
        for (const nlohmann::json& j : *joints)
          if (uint64_t k = 0; index(&j, k)) visitNode(visitNode, k, 0);
  if (const nlohmann::json* anims = jsonMember(gltf, "animations"); anims && anims->is_array())
    for (const nlohmann::json& a : *anims)
      if (const nlohmann::json* channels = jsonMember(a, "channels"); channels && channels->is_array())
        for (const nlohmann::json& c : *channels)
          if (const nlohmann::json* target = jsonMember(c, "target"))
            if (uint64_t k = 0; index(jsonMember(*target, "node"), k)) visitNode(visitNode, k, 0);
  return order;
}

}  // namespace firstshot
