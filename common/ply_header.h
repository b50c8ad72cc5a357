#pragma once
/// @file ply_header.h
/// A strict check of a PLY file's header, made before assimp reads the file: assimp 5.2's PLY importer
/// loops forever or crashes on some malformed headers (found by fuzzing, docs/robustness.md).
#include <istream>
#include <string>

namespace fs {

/// What is wrong with the PLY header at the start of @p in, or "" if it is well formed: the line "ply",
/// one "format ascii|binary_little_endian|binary_big_endian 1.0" line, then only "comment …",
/// "obj_info …", "element <name> <count>", "property <type> <name>" and
/// "property list <count type> <type> <name>" lines (a property after an element), up to "end_header".
/// Line ends may be "\n" or "\r\n". The message names the line.
std::string plyHeaderDefect(std::istream& in);

}  // namespace fs
