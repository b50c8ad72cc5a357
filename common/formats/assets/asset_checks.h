#pragma once
/// @file asset_checks.h
/// Checks of mesh files made before assimp reads them, for the malformations assimp 5.2 does not survive
/// (found by fuzzing, docs/robustness.md): its PLY importer loops forever or crashes on some malformed
/// headers, its GLB importer allocates whatever a chunk's length field says.
#include <cstdint>
#include <istream>
#include <string>

namespace firstshot {

/// What is wrong with the PLY header at the start of @p in, or "" if it is well formed: the line "ply",
/// one "format ascii|binary_little_endian|binary_big_endian 1.0" line, then only "comment …",
/// "obj_info …", "element <name> <count>", "property <type> <name>" and
/// "property list <count type> <type> <name>" lines (a property after an element), up to "end_header".
/// Line ends may be "\n" or "\r\n". The message names the line.
std::string plyHeaderDefect(std::istream& in);

/// What is wrong with the header of the binary glTF (.glb) file at the start of @p in, holding @p size
/// bytes, or "": the length in the 12-byte header and every chunk's length must fit the file
/// (version 2: chunks of u32 length, u32 type, data; version 1: one content chunk).
std::string glbHeaderDefect(std::istream& in, uint64_t size);

}  // namespace firstshot
