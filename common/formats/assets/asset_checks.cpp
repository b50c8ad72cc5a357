// Checks of PLY and GLB headers before assimp reads the files (common/formats/assets/asset_checks.h).
#include "common/formats/assets/asset_checks.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <sstream>
#include <vector>

namespace firstshot {
namespace {

bool isScalarType(const std::string& t) {
  static constexpr std::array<const char*, 16> kTypes = {"char",  "uchar",  "short", "ushort", "int",   "uint",
                                                         "float", "double", "int8",  "uint8",  "int16", "uint16",
                                                         "int32", "uint32", "float32", "float64"};
  return std::any_of(kTypes.begin(), kTypes.end(), [&](const char* k) { return t == k; });
}

/// The words of @p line (split at spaces and tabs).
std::vector<std::string> words(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> w;
  for (std::string x; s >> x;) w.push_back(x);
  return w;
}

}  // namespace

std::string plyHeaderDefect(std::istream& in) {
  constexpr size_t kMaxLine = 4096, kMaxLines = 10000;
  bool element = false;
  std::string line;
  for (size_t number = 1; number <= kMaxLines; ++number) {
    line.clear();
    for (int c; (c = in.get()) != EOF && c != '\n';) {
      if (line.size() == kMaxLine) return "header line " + std::to_string(number) + " is too long";
      line.push_back(char(c));
    }
    if (!in && line.empty()) return "the header ends before end_header";
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = "header line " + std::to_string(number) + " (\"" + line.substr(0, 40) + "\")";
    const std::vector<std::string> w = words(line);
    if (number == 1) {
      if (line != "ply") return "not a PLY file (the first line is not \"ply\")";
      continue;
    }
    if (number == 2) {
      if (w.size() != 3 || w[0] != "format" || w[2] != "1.0" ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        return where + ": expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"";
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") return w.size() == 1 ? "" : where + ": unexpected words after end_header";
    if (w[0] == "element") {
      if (w.size() != 3 || w[2].find_first_not_of("0123456789") != std::string::npos || w[2].size() > 10)
        return where + ": expected \"element <name> <count>\"";
      element = true;
    } else if (w[0] == "property") {
      if (!element) return where + ": a property before any element";
      const bool scalar = w.size() == 3 && isScalarType(w[1]);
      const bool list = w.size() == 5 && w[1] == "list" && isScalarType(w[2]) && isScalarType(w[3]);
      if (!scalar && !list) return where + ": expected \"property <type> <name>\" or \"property list <type> <type> <name>\"";
    } else {
      return where + ": unknown keyword \"" + w[0].substr(0, 40) + "\"";
    }
  }
  return "the header has more than " + std::to_string(kMaxLines) + " lines";
}

std::string glbHeaderDefect(std::istream& in, uint64_t size) {
  auto u32 = [&](uint32_t& v) { return bool(in.read(reinterpret_cast<char*>(&v), 4)); };
  uint32_t magic = 0, version = 0, length = 0;
  if (!u32(magic) || !u32(version) || !u32(length)) return "truncated GLB header";
  if (std::memcmp(&magic, "glTF", 4) != 0) return "not a binary glTF file (wrong magic)";
  if (length > size || length < 12) return "the GLB header's length (" + std::to_string(length) + " bytes) does not match the file";
  if (version == 1) {  // content length u32, content format u32, then the JSON content
    uint32_t content = 0, format = 0;
    if (!u32(content) || !u32(format) || content > length - 12) return "the GLB content length does not fit the file";
    return "";
  }
  if (version != 2) return "GLB version " + std::to_string(version) + " (expected 1 or 2)";
  for (uint64_t at = 12; at < length;) {
    uint32_t chunk = 0, type = 0;
    if (length - at < 8 || !u32(chunk) || !u32(type)) return "truncated GLB chunk header at byte " + std::to_string(at);
    if (chunk > length - at - 8) return "a GLB chunk's length (" + std::to_string(chunk) + " bytes) does not fit the file";
    in.seekg(std::streamoff(chunk), std::ios::cur);
    at += 8 + uint64_t(chunk);
  }
  return "";
}

}  // namespace firstshot
