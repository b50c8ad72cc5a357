#pragma once
/// @file cache.h
/// The store of an irradiance cache (Ward, Rubinstein & Clear 1988, "secondary method"): records
/// of indirect irradiance, the weight of eq. 5 with the acceptance w > 1/a, the "in front" test of
/// eq. 6, Ward & Heckbert's (1992) gradients, and one octree per diffuse bounce level (§3.3, §3.4).
///
/// Concurrency: lookups never lock. Inserts into one level are serialised by that level's mutex
/// and publish nodes and records with release stores that lookups read with acquire loads;
/// records are immutable once published except their radius, an atomic that neighbour clamping
/// only lowers. So one cache can be shared by all render threads.
#include <atomic>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "common/util/math.h"

namespace firstshot {

/// One irradiance value E_i computed at P_i by the primary method.
struct IrradianceRecord {
  Vec3 p{0.0f};                 ///< position P_i
  Vec3 n{0.0f, 0.0f, 1.0f};     ///< unit normal N_i, on the side the irradiance was gathered
  Color E{0.0f};                ///< irradiance E_i, W/m²
  /// |E_i − E'_i|/√2 for a second, independent gather E'_i at the same point: one draw of E_i's standard error, W/m²;
  /// −1 where none was made (only --integrator auto's pilot makes them, for some level-0 records).
  Color spread{-1.0f};
  /// R_i: harmonic mean distance to the surfaces seen from P_i (m), lowered by neighbour clamping.
  float R = std::numeric_limits<float>::infinity();
  float Rmin = 0.0f;            ///< the radius used is clamp(R, Rmin, Rmax) (pixel-footprint clamping)
  float Rmax = std::numeric_limits<float>::infinity();
  Vec3 gradT[3]{Vec3(0.0f), Vec3(0.0f), Vec3(0.0f)};  ///< translational gradient ∂E_c/∂P per colour channel c, W/m³
  Vec3 gradR[3]{Vec3(0.0f), Vec3(0.0f), Vec3(0.0f)};  ///< rotational gradient per channel: E_c(N) ≈ E_c + gradR[c]·(N_i × N)
  /// The part of space P_i lies in, where the light a record holds differs from its neighbours' (the irradiance
  /// cache's luminaire boxes: inside one, its light reflected inside is indirect light; outside, its exit light is
  /// direct): a record serves only lookups of its own zone. 0 where there are none.
  int32_t zone = 0;

  /// The radius R_i the weights use.
  float radius() const { return std::min(std::max(R, Rmin), Rmax); }
};

/// Ward's weight (eq. 5) of a record at P_i, N_i, R_i for the point P with normal N:
/// 1 / (|P − P_i|/R_i + √(1 − N·N_i)). Infinite at P = P_i, N = N_i.
float irradianceWeight(const Vec3& pi, const Vec3& ni, float Ri, const Vec3& p, const Vec3& n);

/// Eq. 6: d_i(P) = (P − P_i)·(N(P) + N(P_i))/2. Negative: P_i lies in front of P (the record may
/// sit on an object that shadows P) and must not be used.
float inFrontDistance(const Vec3& pi, const Vec3& ni, const Vec3& p, const Vec3& n);

/// E_i carried to (P, N) by the gradients: E_i + (N_i × N)·∇r E_i + s·(P − P_i)·∇t E_i, each
/// channel ≥ 0, with s = min(1, R_i / radius()) so that a domain widened by footprint clamping
/// does not carry the translational gradient further than R_i.
Color extrapolateIrradiance(const IrradianceRecord& r, const Vec3& p, const Vec3& n);

/// Running weighted sum of eq. 5 over accepted records.
struct IrradianceEstimate {
  Color sum{0.0f};   ///< Σ w_i E_i(P)
  double weight = 0; ///< Σ w_i
  int count = 0;     ///< |S|
  Color value() const { return weight > 0 ? sum / float(weight) : Color(0.0f); }
};

/// Records of one or more diffuse bounce levels, each level in its own octree over a global cube.
class IrradianceCache {
 public:
  /// @param lo, hi       bounds of every surface (the global cube is grown from them)
  /// @param accuracy     a per level (level ℓ uses accuracy[ℓ]); the number of levels is its size
  IrradianceCache(const Vec3& lo, const Vec3& hi, std::vector<float> accuracy);
  ~IrradianceCache();
  IrradianceCache(const IrradianceCache&) = delete;
  IrradianceCache& operator=(const IrradianceCache&) = delete;

  int levels() const { return int(levels_.size()); }
  float accuracy(int level) const { return accuracy_[size_t(level)]; }
  /// Side of the global cube, m.
  float extent() const { return size_; }

  /// The secondary method at level @p level: adds w_i·E_i(P) over every record with
  /// w_i(P) > 1/a, N·N_i > 0 and d_i(P) ≥ −tolerance (eq. 6) to @p est, found by the octree
  /// search of §3.3. With @p gradients the values are extrapolated (extrapolateIrradiance).
  /// @p relax ∈ [1, 2] widens the acceptance to w_i > 1/(relax·a) (domains relax·a·R_i). Only records of @p zone
  /// (IrradianceRecord::zone) count.
  void lookup(int level, const Vec3& p, const Vec3& n, bool gradients, IrradianceEstimate& est, float relax = 1.0f,
              int32_t zone = 0) const;
  /// True if a record of @p level and @p zone would be accepted at (p, n).
  bool covers(int level, const Vec3& p, const Vec3& n, int32_t zone = 0) const;
  /// Copies every level's octree into compact arrays (nodes by index, each node's records' positions, normals, radii
  /// and zones side by side) that lookup() and covers() search instead, with the same results in the same order, until
  /// the next insert(). For a cache that is read more than written (the two-pass fill between its merges, the render
  /// after it): a lookup reads tens of records for each one it accepts, scattered over memory in the octree's lists.
  /// Not while another thread inserts.
  void freeze();

  /// Stores @p r at @p level in the node that contains P_i and whose side s satisfies
  /// 2·a·R_i < s ≤ 4·a·R_i (or the root when the domain exceeds the cube). With
  /// @p neighbourClamp, first R_i ≤ R_j + |P_i − P_j| and then R_j ≤ R_i + |P_i − P_j| over the
  /// neighbours j: the records within R_i of P_i or whose doubled valid domain 2·a·R_j contains
  /// P_i (Křivánek et al. 2006), carried on to the neighbours of every record that shrinks; the
  /// second step only with @p shrinkNeighbours. Thread-safe.
  void insert(int level, IrradianceRecord r, bool neighbourClamp, bool shrinkNeighbours = true);
  /// Neighbour clamping of @p r against this cache without changing it (R_i ≤ R_j + |P_i − P_j|).
  void clampToNeighbours(int level, IrradianceRecord& r) const;

  size_t size(int level) const;
  size_t size() const;
  /// The records of @p level in insertion order, with their current radii.
  std::vector<IrradianceRecord> records(int level) const;
  /// Depth of the octree node holding each record of @p level (root = 0), in insertion order. For tests.
  std::vector<int> nodeDepths(int level) const;
  /// Side of the cube at depth @p depth.
  float nodeSize(int depth) const { return std::ldexp(size_, -depth); }

 private:
  struct Stored;
  struct Node;
  struct Level;
  struct Frozen;
  /// Calls f on the records of every node whose cube, grown by max(radius, nodeReach · its side), contains p.
  template <typename F>
  void visit(const Level& level, const Vec3& p, float radius, float nodeReach, F&& f) const;
  /// As visit(), over the frozen copy: f(index of the record in Frozen's arrays), in the same order; with @p prune,
  /// not into a node whose records' domains at relax 1, its own and those below it, all leave out p.
  template <typename F>
  void visitFrozen(const Frozen& frozen, const Vec3& p, float nodeReach, bool prune, F&& f) const;
  /// Calls f(record, distance, R_j) for the neighbours of a record at p with radius R: the records
  /// within R of p, or whose doubled valid domain 2·a·R_j contains p.
  template <typename F>
  void visitNeighbours(int level, const Vec3& p, float R, F&& f) const;

  std::vector<float> accuracy_;
  Vec3 origin_{0.0f};  ///< minimum corner of the global cube
  float size_ = 1.0f;  ///< its side
  float frontTolerance_ = 0.0f;
  std::vector<std::unique_ptr<Level>> levels_;
};

}  // namespace firstshot
