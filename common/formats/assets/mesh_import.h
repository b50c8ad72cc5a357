#pragma once
/// @file mesh_import.h
/// Reading meshes and whole scenes from asset files (OBJ, glTF, GLB, PLY) through assimp.
#include <string>
#include <vector>

#include "common/scene/scene_desc.h"

namespace firstshot {

/// Triangles of every mesh in an asset file, node transforms applied (file units kept).
struct MeshData {
  std::vector<Vec3d> vertices;
  std::vector<Face> faces;  ///< all triangles
  std::vector<Vec2> uv;     ///< per face corner as ShapeDesc::uv (the first set); empty when no mesh has any, (0, 0) for one without
  std::vector<Vec3> normals;  ///< per face corner as ShapeDesc::normals; empty when no mesh has any, 0 for one without
  /// Per face corner as ShapeDesc::tangents (glTF TANGENT); empty when no mesh has any.
  std::vector<Vec3> tangents, bitangents;
};

/// Loads all triangles of a mesh file, degenerate ones kept (the scene's loader skips them: skipDegenerateFaces).
/// @p element names the scene element that asked for it.
/// @throws InputError when the file is missing, a Git LFS pointer, unreadable (a glTF buffer missing, an LFS
/// pointer or short: named so), or holds no triangles.
MeshData loadMeshFile(const std::string& path, const std::string& sceneFile, const std::string& element);

/// Imports an asset file as a whole scene: each mesh becomes a shape with its texture coordinates (set 0); OBJ/PLY
/// materials keep their diffuse colour as albedo (map_Kd as its texture) and their emissive colour as emission
/// (making the mesh an area light), glTF materials are read from the JSON, the base-colour texture as the albedo
/// texture and the others folded into the factors (common/formats/assets/gltf_materials.h); KHR_lights_punctual lights
/// (candela, lux) become point, spot and directional lights in watts; the first camera is used
/// (SceneDesc::camera.given = false when there is none, so validateScene frames the scene). Zero-area and
/// duplicate faces are skipped (skipDegenerateFaces). Rules: docs/scene-format.md, "Asset files as scenes".
/// @throws InputError.
SceneDesc importAssetScene(const std::string& path);

}  // namespace firstshot
