#pragma once
/// @file mitsuba_serialized.h
/// Mitsuba's `.serialized` mesh files (the `serialized` shape of Mitsuba 0.4 to 3): indexed triangle meshes, one or
/// more per file, each compressed with zlib. The layout, all little-endian, per shape:
///
///     uint16 format identifier 0x041C, uint16 version (3 or 4)     — uncompressed
///     one zlib stream:
///       uint32 flags: 0x0001 vertex normals, 0x0002 texture coordinates, 0x0008 vertex colours,
///                     0x0010 face normals (shade flat), 0x1000 single precision, 0x2000 double precision
///       version 4 only: the shape's name, UTF-8, NUL-terminated
///       uint64 vertex count V, uint64 triangle count T
///       positions (3·V reals), then as flagged normals (3·V), texture coordinates (2·V), colours (3·V);
///       reals are float, or double with flag 0x2000
///       triangles: 3·T uint32 vertex indices
///
/// and at the end of the file the byte offset of each shape's header (uint64 in version 4, uint32 in version 3;
/// the first is 0) followed by the uint32 number of shapes, from which `shape_index` finds its shape.
#include <string>

#include "common/formats/assets/mesh_import.h"

namespace firstshot::mitsuba {

/// One shape of a serialized file.
struct SerializedShape {
  /// Its triangles: vertices welded at identical positions as in asset meshes (common/formats/vertex_welder.h), texture
  /// coordinates (Mitsuba's, which are ShapeDesc's: v down from the image's top) and unit normals per face corner.
  /// uv and normals are empty when the file has none; the colours are skipped.
  MeshData mesh;
  std::string name;          ///< the name stored with it (version 4), else empty
  bool faceNormals = false;  ///< the file asks for face normals (flag 0x0010)
};

/// Reads shape @p index (from 0) of the serialized file @p path. @p sceneFile and @p element name the scene
/// element that asks for it.
/// @throws InputError naming @p sceneFile, @p element, @p path, the shape index and what is wrong: a missing file,
/// a wrong format identifier or version, an index past the shapes the file holds, an end-of-file dictionary or
/// compressed stream that is corrupt or cut short, counts the data does not match, an index past the vertices.
SerializedShape readSerializedShape(const std::string& path, int index, const std::string& sceneFile,
                                    const std::string& element);

}  // namespace firstshot::mitsuba
