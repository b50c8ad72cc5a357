#pragma once
/// @file mesh_import.h
/// Reading meshes and whole scenes from asset files (OBJ, glTF, GLB, PLY) through assimp.
#include <string>
#include <vector>

#include "common/scene_desc.h"

namespace fs {

/// Triangles of every mesh in an asset file, node transforms applied (file units kept).
struct MeshData {
  std::vector<Vec3d> vertices;
  std::vector<Face> faces;  ///< all triangles
};

/// Loads all triangles of a mesh file. @p element names the scene element that asked for it.
/// @throws InputError when the file is missing, unreadable, or holds no triangles.
MeshData loadMeshFile(const std::string& path, const std::string& sceneFile, const std::string& element);

/// Imports an asset file as a whole scene: each mesh becomes a shape; materials keep their base
/// colour as diffuse albedo and their emissive colour as emission (making the mesh an area light);
/// KHR_lights_punctual lights become point, spot and directional lights; the first camera is used
/// (SceneDesc::camera.given = false when there is none, so validateScene frames the scene).
/// @throws InputError.
SceneDesc importAssetScene(const std::string& path);

}  // namespace fs
