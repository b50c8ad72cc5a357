#pragma once
/// @file light_clusters.h
/// Light samples of an emissive mesh by need, not by vertex: the vertex samples of its faces
/// (preprocess/light_tessellation.h) merged top-down into clusters, so that a filament of thousands
/// of triangles seen from metres away is a few samples while a panel next to a wall keeps its cells.
///
/// A cluster becomes one sample at its samples' weighted centroid, with their weighted mean normal
/// n̄ = m/|m| (m = Σ w·n) and the weight Σw, their area. A cosine lobe of weight W sends πW·Le in all
/// and, averaged over all directions ω, the intensity W·Le/4 (the mean of max(0, n·ω) over the sphere
/// is 1/4 for any n): with W = Σw the sample sends exactly the cluster's power, and its intensity
/// averaged over directions is exactly the faces' Le·Σ w·max(0, n·ω). Direction by direction it
/// overstates where every face of the cluster faces ω (by Σw/|m| ≤ 1 + tolerance) and understates
/// near n̄'s horizon, where the tilted faces still send light; summed over the clusters of a mesh
/// these errors alternate in sign. (The weight (Σw + |m|)/2, the power in front of n̄ only, put every
/// room face of scenes/bulb-room.json 0.39% darker than the triangles' exact irradiance; Σw within
/// ±0.05%: tests/test_light_clusters.cpp.)
/// It is kept whole when both
///  - its diameter h and its distance d to the nearest receiver in front of it meet the vertex rule's
///    bound C·(h/d)² ≤ tolerance (C = kVertexRuleErrorConstant), and
///  - its normals agree: Σw ≤ (1 + tolerance)·|m|, so that overstatement is at most 1 + tolerance.
/// Otherwise it is split at the median of its widest spread: of the normals while they disagree,
/// else of the positions. Receivers are the faces of every non-emissive shape, clipped to the
/// half-space in front of the plane through the cluster's rearmost sample across its mean normal.
#include "common/scene/scene_desc.h"
#include "preprocess/light_tessellation.h"

namespace firstshot {

/// Merges the samples of @p fine (the tessellation of an emissive shape of @p scene) into clusters
/// for relative accuracy @p tolerance (see the file comment). Deterministic: same input, same
/// output, byte for byte. The triangles of @p fine are kept (they still describe the light).
/// Cost: O(S log S) in the samples plus one scan of the receivers per cluster examined.
/// A cluster whose normals agree is also kept whole once its diameter is at most @p floor (m): the
/// tessellation's floor, raised to keep the samples within kLightSampleBudget.
LightTessellation clusterLightSamples(const SceneDesc& scene, LightTessellation fine, double tolerance, double floor = 0);

}  // namespace firstshot
