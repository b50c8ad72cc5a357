#pragma once
/// @file window.h
/// The "windows" around a light sample: sets of item-buffer views plus one weight per pixel, computed
/// once per resolution R. Views are given in the light's LOCAL frame (z = light normal, spot axis, or
/// the direction a directional light travels) with the eye at the origin; placeWindow() moves them
/// to a light sample in the world. Summing a pixel's weight into the patch it sees gives:
///   Cube:        δω = 4·cos³θp / R²                     (Σ = 4π)   point and spot lights
///   Hemicube:    δω·cosθL                               (Σ = π)    area-light vertices
///   Tetrahedron: δω·cosθL on the triangular regions     (Σ = π)    area-light vertices
///   Ortho:       δA⊥, the pixel's area in m²            (Σ = covered area)  directional lights
/// See docs/firstshot-format.md, "What it holds" (the weights per window) and "Estimators".
#include <string>
#include <vector>

#include "common/util/math.h"
#include "preprocess/view.h"

namespace firstshot {

enum class WindowKind : uint8_t { Cube, Hemicube, Tetrahedron, Ortho };

/// Views and per-pixel weights of one window.
struct Window {
  WindowKind kind = WindowKind::Cube;
  int resolution = 0;                       ///< R, the resolution it was built for
  std::vector<View> views;                  ///< in the light's local frame
  std::vector<std::vector<double>> weights; ///< per view, row-major like the item buffer; 0 = invalid pixel

  /// Σ of all weights (4π, π, π or the covered area).
  double totalWeight() const;
  /// Number of pixels over all views.
  size_t pixelCount() const;
};

/// Six R×R faces of a cube around the eye (point and spot lights). Weight δω.
Window makeCubeWindow(int R);

/// Hemicube around +z (area-light vertices): the top face R×R and the upper halves (R×R/2, above the
/// base plane z = 0) of the four side faces. @p R must be even. Weight δω·cosθL.
Window makeHemicubeWindow(int R);

/// Face resolution of the cubic tetrahedron for a hemicube-equivalent R: round(√2·R), so that its
/// valid pixels (half of each of the three faces) are as many as the hemicube's 3R², i.e. the same
/// mean number of pixels per steradian over the hemisphere. The rendered pixel count is 2× the hemicube's.
int tetraFaceResolution(int R);

/// Cubic tetrahedron (area-light vertices): three faces, apex (1,1,1), base corners (1,1,−2),
/// (1,−2,1), (−2,1,1), its axis (1,1,1)/√3 mapped onto +z. Each face spans [−2,1]² at focal distance 1
/// with W = tetraFaceResolution(R) pixels across; only the triangle u + v ≥ −1 is valid (weight 0 elsewhere).
/// The diagonal u + v = −1 passes through pixel corners, so it halves exactly the cells with
/// i + j = W − 1 (centres on the base plane, where the weight vanishes). Those boundary cells get the
/// integral of δω·cosθL over their valid half-triangle, split into @p subgrid² congruent sub-triangles
/// each sampled at its centroid (exact for the linear factor 1+u+v, O(1/subgrid²) otherwise); every
/// other valid pixel is sampled at its centre. Weight δω·cosθL; sum π to ~1e-6 at R = 512.
Window makeTetraWindow(int R, int subgrid = 16);

/// One orthographic view for a directional light travelling along the unit @p direction: the local
/// frame is Framed(direction) around bounds.centre() (use placeWindow with exactly that position and
/// frame). The view covers the projection of @p bounds with square pixels, R across its longer side; the
/// eye plane lies 1% of the diagonal before the box. Weight δA⊥ (m²) on every pixel.
Window makeOrthoWindow(int R, const Bounds3d& bounds, const Vec3d& direction);

/// Crops every view of @p window to the smallest pixel rectangle holding its weights > 0 and drops
/// views without any (a spot's cube outside its cone). The pixels kept keep their centres (the
/// image-plane bounds move by whole pixels) and weights; the estimators never use a weight-0 pixel,
/// so a cropped window gives the same factors for fewer pixels rendered.
void cropToWeights(Window& window);

/// The window's views moved to a light sample: eye = position + frame·localEye + eyeOffset·frame.n,
/// basis vectors rotated by @p frame (local x,y,z → frame.s, frame.t, frame.n).
std::vector<View> placeWindow(const Window& window, const Vec3d& position, const Framed& frame, double eyeOffset = 0.0);

/// Eye offset along the light normal for area-light vertices: @p relative × the scene diagonal. The
/// default (1e-5) keeps the eye ~100 float ulps above the light's plane for scene coordinates of the
/// order of the diagonal, so the light's own plane and coplanar neighbours (e.g. the ceiling around a
/// ceiling light) fall strictly below the hemicube's base plane; it is 10× the default near plane.
double areaLightEyeOffset(const Bounds3d& sceneBounds, double relative = 1e-5);

/// Parses "cube" | "hemicube" | "tetra" (for settings); @throws std::invalid_argument otherwise.
WindowKind parseWindowKind(const std::string& name);

}  // namespace firstshot
