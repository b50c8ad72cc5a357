#pragma once
/// @file light_clusters.h
/// Light samples of an emissive mesh by need, not by vertex: the vertex samples of its faces
/// (preprocess/light_tessellation.h) merged top-down into clusters, so that a filament of thousands
/// of triangles seen from metres away is a few samples while a panel next to a wall keeps its cells.
///
/// A cluster becomes one sample at its samples' weighted centroid, with their weighted mean normal
/// n̄ = m/|m| (m = Σ w·n) and the weight (Σw + |m|)/2. A face tilted by β from n̄ sends the fraction
/// (1 + cos β)/2 of its power into the half-space in front of n̄, so the cluster sends
/// π·Le·Σ w·(1 + cos β)/2 = π·Le·(Σw + |m|)/2 there: the sample keeps that power exactly. Where every
/// face of the cluster faces a direction ω its intensity Le·m·ω is overstated by the factor
/// (Σw + |m|)/(2|m|); the light its tilted faces send beyond n̄'s horizon, (Σw − |m|)/2, is dropped.
/// (The weight Σw would overstate every direction in front by Σw/|m|; |m| would drop that light.
/// On an emissive icosphere they put the first-shot image at +0.35% and −0.30% of NEE.)
/// It is kept whole when both
///  - its diameter h and its distance d to the nearest receiver in front of it meet the vertex rule's
///    bound C·(h/d)² ≤ tolerance (C = kVertexRuleErrorConstant), and
///  - its normals agree: Σw ≤ (1 + tolerance)·|m|, so that overstatement is at most 1 + tolerance/2.
/// Otherwise it is split at the median of its widest spread: of the normals while they disagree,
/// else of the positions. Receivers are the faces of every non-emissive shape, clipped to the
/// half-space in front of the plane through the cluster's rearmost sample across its mean normal.
#include "common/scene_desc.h"
#include "preprocess/light_tessellation.h"

namespace fs {

/// Merges the samples of @p fine (the tessellation of an emissive shape of @p scene) into clusters
/// for relative accuracy @p tolerance (see the file comment). Deterministic: same input, same
/// output, byte for byte. The triangles of @p fine are kept (they still describe the light).
/// Cost: O(S log S) in the samples plus one scan of the receivers per cluster examined.
/// A cluster whose normals agree is also kept whole once its diameter is at most @p floor (m): the
/// tessellation's floor, raised to keep the samples within kLightSampleBudget.
LightTessellation clusterLightSamples(const SceneDesc& scene, LightTessellation fine, double tolerance, double floor = 0);

}  // namespace fs
