#pragma once
/// @file light_tree.h
/// A binary tree over emitters for choosing one of many lights in proportion to an estimate of
/// its contribution at a shading point (a light BVH: Conty Estevez & Kulla 2018, pbrt-v4's
/// BVHLightSampler; our own construction). Built once, then read-only and thread-safe.
///
/// Construction splits each node where the cost Σ φ·M_Ω·(box area) of the two halves is least
/// (12 buckets per axis), so that emitters that are close and face alike share a subtree. A node
/// of at most maxLeaf emitters that may be grouped (e.g. small patches) becomes one leaf, inside
/// which an emitter is chosen in proportion to its power: fewer levels to descend.
/// Sampling descends from the root choosing a child with probability proportional to its
/// LightBounds::importance; pmf() walks the same path (each emitter's bit trail) with the same
/// arithmetic, so the probability it returns is exactly the one sample() reports.
#include <cstdint>
#include <memory>
#include <vector>

#include "common/util/math.h"
#include "render/lights/light_bounds.h"

namespace firstshot {

/// A regular grid over the scene whose cells may carry visibility factors for a light tree's top
/// nodes: the share of rays from surfaces in the cell that reach the emitters under each node.
struct VisibilityGrid {
  Vec3 origin{0.0f};
  float cell = 1.0f;              ///< cell edge, m
  int nx = 0, ny = 0, nz = 0;
  std::vector<int32_t> row;       ///< per cell (x fastest): its row of factors, or −1
  size_t rows = 0;

  /// The grid cell of @p p (clamped to the grid), as an index into row.
  size_t cellOf(const Vec3& p) const {
    auto axis = [this](float v, float o, int n) { return std::clamp(int((v - o) / cell), 0, n - 1); };
    return (size_t(axis(p.z, origin.z, nz)) * size_t(ny) + size_t(axis(p.y, origin.y, ny))) * size_t(nx) +
           size_t(axis(p.x, origin.x, nx));
  }
  int32_t rowOf(const Vec3& p) const { return row.empty() ? -1 : row[cellOf(p)]; }
};

class LightTree {
 public:
  LightTree() = default;
  /// Builds the tree over @p emitters; emitter k keeps index k. Emitters with zero power are
  /// never chosen. Emitters with the same nonzero (*groupable)[k] (e.g. the patches, or the triangles
  /// of one area light) may share leaves of up to @p maxLeaf; 0 keeps an emitter in a leaf of its own.
  explicit LightTree(const std::vector<LightBounds>& emitters, const std::vector<uint32_t>* groupable = nullptr,
                     int maxLeaf = 8);

  bool empty() const { return nodes_.empty(); }
  /// Depth of the deepest leaf (0 for a single emitter).
  int depth() const { return depth_; }

  /// Chooses an emitter for the receiver at @p p with unit normal @p n (zero: any direction)
  /// from @p u ∈ [0,1). @return false when no emitter can light @p p; else @p index and its
  /// probability @p pmf > 0. @p rest, if given, gets u's place within the chosen emitter's share
  /// of [0,1), rescaled to [0,1): a uniform number independent of the choice, which the caller
  /// may reuse for the point on the emitter (the choice and the point then share one stratified
  /// dimension).
  bool sample(const Vec3& p, const Vec3& n, float u, uint32_t& index, float& pmf, float* rest = nullptr) const;

  /// The probability with which sample(p, n, ·) chooses emitter @p index (0 if it never does).
  float pmf(const Vec3& p, const Vec3& n, uint32_t index) const;

  // Visibility: the descent multiplies the importance of a node at depth ≤ D by a factor of the
  // receiver's grid cell, ε + (1 − ε)·v with v the estimated share of unoccluded rays to it.
  /// The cut at depth @p D: the nodes at depth D and the leaves above it, in tree order.
  std::vector<uint32_t> cut(int D) const;
  /// The emitters under node @p node (a subtree's emitters are contiguous), with their powers.
  void emittersUnder(uint32_t node, std::vector<uint32_t>& emitters, std::vector<float>& power) const;
  /// Sets the factors: @p cutVisibility[r·cut.size() + k] = v of cut node k from grid row r;
  /// the nodes above the cut get the power-weighted mean of those below. @p epsilon > 0 keeps
  /// every emitter reachable.
  void setVisibility(std::shared_ptr<const VisibilityGrid> grid, int D, const std::vector<float>& cutVisibility, float epsilon);

 private:
  /// The bounds in the form the descent evaluates (LightBounds with its sphere and sin θo precomputed).
  struct Node {
    Vec3 c{0.0f};
    float r2 = 0.0f;
    Vec3 w{0.0f, 0.0f, 1.0f};
    float phi = 0.0f;
    float cosO = -1.0f, sinO = 0.0f, cosE = 0.0f;
    uint32_t child = 0;  ///< interior: index of the second child (the first is this + 1); leaf: first slot in leaf_
    uint16_t count = 0;  ///< leaf: number of emitters; 0 for interior nodes
    bool twoSided = false;
    uint8_t depth = 0;
    int32_t top = -1;            ///< index among the nodes with visibility factors, or −1
    uint32_t first = 0, end = 0; ///< the subtree's emitters: leaf_[first, end)
    float importance(const Vec3& p, const Vec3& n) const;
  };
  struct Item {
    LightBounds bounds;
    Vec3 centroid{0.0f};
    uint32_t index = 0;
  };
  uint32_t build(std::vector<Item>& items, size_t begin, size_t end, uint64_t trail, int depth);
  /// Probability of the first child of interior node @p node; false if neither child can light p.
  /// @p vis: the receiver's row of visibility factors (nullptr: none).
  bool firstChildProbability(uint32_t node, const Vec3& p, const Vec3& n, const float* vis, float& p0) const;
  /// The leaf reached from the root by @p u, and the probability of that path (0: none).
  uint32_t descend(const Vec3& p, const Vec3& n, float& u, float& pmf) const;
  const float* visibilityRow(const Vec3& p) const;

  std::vector<Node> nodes_;
  std::vector<uint64_t> trail_;      ///< per emitter: bit k = 1 where the path goes to the second child at depth k
  std::vector<uint8_t> trailDepth_;  ///< per emitter: depth of its leaf (255: not in the tree)
  std::vector<float> inLeaf_;        ///< per emitter: its power over its leaf's
  std::vector<float> power_;         ///< per emitter: its power, W
  std::vector<uint32_t> leaf_;       ///< emitters of the leaves, leaf by leaf
  std::vector<float> leafCdf_;       ///< beside leaf_: cumulative power share within the leaf (last 1)
  const std::vector<uint32_t>* groupable_ = nullptr;  ///< during construction only
  int maxLeaf_ = 1;
  std::shared_ptr<const VisibilityGrid> grid_;  ///< shared by the sampler's trees and its copies
  std::vector<float> visibility_;    ///< per grid row: one factor per top node
  size_t topCount_ = 0;
  int depth_ = 0;
};

}  // namespace firstshot
