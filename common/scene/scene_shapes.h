#pragma once
/// @file scene_shapes.h
/// Builders that resolve the scene file's shape primitives into world-space polygons.
#include <array>

#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/scene_desc.h"

namespace firstshot::shapes {

/// A quad from 4 vertices (counter-clockwise seen from the front). A planar convex quad stays one
/// face; a non-planar one is split into two triangles along the shorter diagonal. Degenerate input is
/// kept as is for validateScene to report.
void makeQuad(ShapeDesc& s, const std::array<Vec3d, 4>& v);

/// An axis-aligned box: 6 quads, normals outward.
void makeBox(ShapeDesc& s, const Vec3d& lo, const Vec3d& hi);

/// A sphere tessellated from an icosahedron, @p subdivisions times (20·4^k triangles), normals outward.
void makeSphere(ShapeDesc& s, const Vec3d& center, double radius, int subdivisions);

/// Applies an affine transform; a mirroring transform reverses the winding so normals stay outward.
void transform(ShapeDesc& s, const Mat4d& m);

/// Reverses the winding (and so the normals) of every face; shading normals are reversed with them.
void flip(ShapeDesc& s);

/// Gives sphere @p s (makeSphere, centre @p center) the sphere's own normals at its corners as shading
/// normals, so that it shades smooth ("smooth": true).
void smoothSphere(ShapeDesc& s, const Vec3d& center);

/// Area of one face, in double.
double faceArea(const ShapeDesc& s, const Face& f);

}  // namespace firstshot::shapes
