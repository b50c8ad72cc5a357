// The strict PLY header check (common/ply_header.h).
#include "common/ply_header.h"

#include <algorithm>
#include <array>
#include <sstream>
#include <vector>

namespace fs {
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

}  // namespace fs
