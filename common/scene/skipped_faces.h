#pragma once
/// @file skipped_faces.h
/// Faces that other renderers tolerate and firstshot skips: zero-area faces and duplicates. Loaders call
/// skipDegenerateFaces() once the faces of a scene are final, before validateScene(), so that nothing later sees
/// them; each input file with skipped faces gets one line on stderr (docs/scene-format.md, "Skipped faces").
#include <string>
#include <vector>

#include "common/scene/scene_desc.h"

namespace firstshot {

/// Whether face @p f of @p s (3 or 4 vertex indices, all in range) has zero area: its longest edge is zero, or its
/// area is at most 1e-10 × the longest edge squared (collinear or coincident vertices, in m²).
bool hasZeroArea(const ShapeDesc& s, const Face& f);

/// Removes from every shape of @p scene its zero-area faces and every face with the same vertex positions as an
/// earlier face of the same shape (the same cyclic order, any starting vertex, so the same winding). A shape left
/// without faces is removed from scene.shapes (area lights' LightDesc::shape indices follow; a light of a removed
/// shape is removed). Shapes with a non-finite vertex or a malformed face are left whole, for validateScene to
/// refuse. Prints one line per input file (a mesh file, or the scene file for its own shapes) with skipped faces:
///   "scene.json: skipped 155 of 262661 triangles of Mesh353.obj (150 zero-area, 5 duplicates)".
/// @throws InputError when no shape is left.
/// @return the lines printed (without their newlines), in the order of the shapes.
std::vector<std::string> skipDegenerateFaces(SceneDesc& scene);

}  // namespace firstshot
