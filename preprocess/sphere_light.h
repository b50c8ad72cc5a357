#pragma once
/// @file sphere_light.h
/// An emissive sphere as isotropic light samples inside it: one at its centre, or twelve on a shell.
///
/// A point source's irradiance at a receiver point x of normal n, E(p) = I·n·(p − x)/|p − x|³, is a
/// harmonic function of the source position p (a derivative of 1/|p − x|) wherever x sees p above its
/// horizon. Its mean over a sphere about c is therefore E(c) (the mean value property), and so a
/// sphere of uniform radiance Le and area A lights x exactly as a point of intensity Le·A/4 at its
/// centre (Lambert's sphere theorem; A/4 is its projected area in every direction), and nearly as
/// the twelve vertices of an icosahedron of radius ρ about c, each of a twelfth of it: they average
/// every harmonic of degree 1 to 5 to zero (a spherical 5-design), which leaves an error of order
/// (ρ/D)⁶ at a distance D (measured: at most kShellErrorConstant·(ρ/D)⁶ over receivers facing the
/// sphere, D/r from 1.05 to 3).
///
/// One centre sample gives the irradiance but sharp shadows; the twelve give a penumbra, the mean of
/// twelve sharp shadows, as wide as the sphere's own (seen from any direction a shell of radius
/// r·√3/2 has the second moment of the sphere's disk, r²/2) unless a near receiver shrinks the shell
/// to keep kShellErrorConstant·(ρ/(r + d))⁶ ≤ tolerance, d the distance to the nearest receiver. The
/// vertex rule's samples on the surface (preprocess/light_clusters.h) approach the same irradiance only
/// as their caps' normals agree: 150-250 hemicubes for a sphere at light_tolerance 0.01-0.04, however
/// far its receivers are, against one cube or twelve here.
///
/// Rule (automatic light tessellation only): a sphere whose diameter h meets C·(h/d)² ≤ tolerance
/// (kVertexRuleErrorConstant: its sharp shadows then blur less than a cluster kept whole does) is
/// one centre sample; else twelve on the shell. It is sampled on its surface as any emissive mesh
/// instead where a receiver touches it, where the plane of a receiver face within r of it passes
/// through the shell, or where such a plane cuts the sphere and the samples' irradiance at the
/// face's nearest points (which see part of the sphere under their horizon) is off the sphere's own
/// by more than the surface samples' tolerance (light_tolerance as the sample budget relaxes it).
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"

namespace firstshot {

/// The constant K of the twelve samples' error bound K·(ρ/D)⁶ (see the file comment): 3.2-4.4 measured.
inline constexpr double kShellErrorConstant = 5.0;

/// An emissive sphere's centre, radius and area, and how its receivers lie.
struct SphereLightFit {
  Vec3d centre{0.0};
  double radius = 0;      ///< m: the vertices' mean distance to the centre
  double area = 0;        ///< m²: the tessellation's (what the renderer's emitter has)
  double distance = 0;    ///< m: from the sphere's surface to the nearest face of a non-emissive shape
  double shell = 0;       ///< m: ρ, the twelve samples' distance from the centre
  bool cutsShell = false; ///< a receiver touches the sphere, or a face within r has its plane through the shell
  /// Points (and unit normals, toward the sphere) of the faces within r whose planes cut the sphere:
  /// the nearest point of each edge.
  std::vector<std::pair<Vec3d, Vec3d>> cutPoints;
};

/// Light @p lightIndex of @p scene as a sphere, when it is one: an area light on a ShapeType::Sphere
/// shape whose vertices lie within 0.1% of one radius from their centroid (not an ellipsoid), whose
/// faces face outward and whose emission has no texture; its shell for @p tolerance. Empty otherwise.
std::optional<SphereLightFit> fitSphereLight(const SceneDesc& scene, uint32_t lightIndex, double tolerance);

/// The isotropic samples (LightSampleKind::Point) of light @p lightIndex when it is a sphere that the
/// rule in the file comment takes at @p tolerance, the surface samples' being @p surfaceTolerance: one
/// at its centre or twelve on its shell, their powers (π·Le·A in all, W) equal. Empty otherwise.
std::vector<LightSample> sphereLightSamples(const SceneDesc& scene, uint32_t lightIndex, double tolerance,
                                            double surfaceTolerance);

/// The irradiance (W/m² per unit radiance) a uniform sphere (@p fit) gives point @p x of unit normal
/// @p n, by a quadrature of its surface (4096 points, Fibonacci): what the samples are checked against.
double sphereIrradiance(const SphereLightFit& fit, const Vec3d& x, const Vec3d& n);

}  // namespace firstshot
