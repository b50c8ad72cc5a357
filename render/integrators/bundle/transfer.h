#pragma once
/// @file transfer.h
/// Ray-bundle stochastic iteration (Szirmay-Kalos 1999; with incoming first-shot, the first-shot
/// paper's §5): the global transfer and its per-element state. docs/bundle.md derives the estimators.
///
/// Iteration k draws ω_k uniform on the sphere and B×B parallel lines along it (BundleGrid). Along a
/// line every surface it crosses is found in order; each consecutive pair exchanges radiance both
/// ways: the nearer one's outgoing radiance towards +ω_k arrives at the farther one, and the farther
/// one's towards −ω_k at the nearer one. All lines of an iteration are parallel, so each side of an
/// element receives from one direction only (±ω_k, whichever lies on that side) and one value per
/// element side is stored, the unbiased line-density estimate
///     I_k(j, s) = δA⊥/A_j · Σ_{lines arriving at side s of j} L_arriving      [W/(m² sr)]
/// whose expectation over the grid offset is (1/A_j)∫_{A_j} L_in(x, ω_in)|cos θ_in| dA.
/// For a given side, ω_in is uniform over its hemisphere (pdf 1/2π, since both ±ω_k are used), so
///     L_r(j, s, ω) ≈ 2π · f_r(ω_in, ω) · I_k(j, s)
/// is an unbiased estimate of the patch-averaged reflected radiance (the cos θ_in is in the line
/// density). (A one-way transfer, lines along +ω_k only, would have 4π here.)
///
/// Outgoing radiance of element j on side s towards w = ±ω_k (the one on side s) in iteration k:
///   Le (emitter front side, unless a first-shot table replaces that light)
///   + Σ_i Le_i r_ij f_r(ω_i, w)            first-shot, at the patch centroid (diffuse: f·E per side)
///   + f_r(−d_l, w)·D_k(l, j)               each kept directional light l (its own bundle, below)
///   + 2π f_r(ω_in, w)·(I_{k−1} + P_{k−1})(j, s)
/// Kept point and spot lights emit as themselves: each iteration they send one line along +ω_k and
/// one along −ω_k from their position; the element side first hit gets P_k += I_light(dir)/A_j
/// (so that 2π f P_k has the expectation (1/A_j)∫_{Ω_j} f I dω of the patch-averaged direct light).
/// A kept directional light (E⊥, direction d) gets an extra bundle along d each iteration; the side
/// first hit gets D_k += E⊥·δA⊥/A_j, an unbiased estimate of its patch-averaged direct irradiance.
/// Delta surfaces (mirror, glass) block lines and neither reflect nor pass radiance in the transfer.
///
/// Bounce orders (--max-depth, docs/irradiance-cache.md "What --max-depth counts"): with orders()
/// = O the state is kept per order b = 0 .. O − 1, the number of reflections the light made before
/// it arrives: I^(b) is the transfer of L^(b), L^(0) = Le, L^(1) = first-shot + f_r·D + 2π f_r·(I^(0)
/// + P), L^(b) = 2π f_r·I^(b−1); light of order O and more is never made. A surface seen at path
/// vertex k then takes orders b ≤ D − 1 − k, exactly the path tracer's depth D. With O = 1 and
/// lumped() every order is in one state (the recurrence above summed over b): every bounce, for
/// depths beyond kMaxOrders.
///
/// Deterministic: lines are traced in parallel in fixed chunks (a grid row each) that record their
/// exchanges (links: target and source slot); the links are then summed chunk by chunk in row order,
/// every order at once, so the state is bit-identical for any number of threads. With several MPI
/// ranks (build()'s @p comm) each rank traces the rows comm.mine() deals to it and the rows' links
/// (and the directional lights' deposits) are exchanged before the sum, so every rank holds
/// the state of one process, bit for bit (the point lights' few lines are traced by every rank).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "common/util/comm.h"
#include "common/util/math.h"
#include "render/integrators/bundle/bundle_grid.h"
#include "render/integrators/bundle/elements.h"
#include "render/lights/next_event.h"
#include "render/scene/render_scene.h"

namespace firstshot {

struct BundleSettings {
  int resolution = 256;  ///< B: lines per side of the grid (B² lines per bundle); docs/bundle.md for the default
  BundleDirections directions = BundleDirections::Random;
  /// Find a line's surfaces with one all-hits query (EmbreeScene::allHits) instead of successive
  /// closest hits (the default; measured faster, docs/bundle.md). The same state either way up to
  /// hits closer together than the successive-hit offset.
  bool allHits = false;
};

class BundleTransfer {
 public:
  /// The most bounce orders kept apart (a --max-depth up to this is followed exactly); deeper
  /// depths carry every order in one state. The state takes 2·O + 3 colours per element side.
  static constexpr int kMaxOrders = 16;

  /// Prepares the elements, the lights and the first-shot sums of @p scene (which must outlive this).
  /// With @p comm (several ranks; null: this process alone) every iterate() is collective: all
  /// ranks run the same iterations, in the same order. @p maxDepth: the longest path in bounces the
  /// image will take (IntegratorOptions::maxDepth): orders 0 .. maxDepth − 1 kept apart if
  /// maxDepth ≤ kMaxOrders, else one lumped state (every bounce).
  void build(const RenderScene& scene, const BundleSettings& settings, Comm* comm = nullptr,
             int maxDepth = kMaxOrders + 1);
  /// Forgets all iterations (the state of "iteration −1": no incoming radiance).
  void reset();
  /// Runs the next iteration (number iterations()) with random numbers keyed by @p seed.
  void iterate(uint64_t seed);
  /// Iterations run since the last reset.
  uint64_t iterations() const { return done_; }

  const BundleElements& elements() const { return elements_; }
  /// ω_k of the last iteration (unit).
  const Vec3& direction() const { return dir_; }
  /// The direction (unit, away from the surface) light of the last iteration came from on side
  /// @p side of a surface with front normal @p n: +ω_k or −ω_k, whichever lies on that side.
  Vec3 incomingDirection(const Vec3& n, int side) const {
    const bool onFront = glm::dot(n, dir_) > 0.0f;
    return (onFront == (side == 0)) ? dir_ : -dir_;
  }
  /// Bounce orders kept apart (1 when lumped()).
  int orders() const { return orders_; }
  /// True if the one state holds every order (a depth beyond kMaxOrders).
  bool lumped() const { return lumped_; }
  /// I_k(e, side): what the bundle of the last iteration brought from the other surfaces, W/(m² sr),
  /// all orders kept.
  Color incoming(uint32_t e, int side) const { return incoming(e, side, orders_ - 1); }
  /// The same, orders 0 .. @p maxOrder only (light reflected at most @p maxOrder times before it
  /// arrives; lumped(): every order whatever @p maxOrder).
  Color incoming(uint32_t e, int side, int maxOrder) const {
    const Color* I = &incoming_[(2 * size_t(e) + size_t(side)) * size_t(orders_)];
    Color sum(0.0f);
    for (int b = 0; b <= std::min(maxOrder, orders_ - 1); ++b) sum += I[b];
    return sum;
  }
  /// P_k(e, side): the same from the kept point and spot lights' own lines, W/(m² sr).
  const Color& incomingPoint(uint32_t e, int side) const { return point_[2 * size_t(e) + side]; }
  /// Kept directional lights (LightSet indices) and their per-element irradiance D_k, W/m².
  const std::vector<uint32_t>& directionalLights() const { return directional_; }
  const Color& directionalIrradiance(size_t d, uint32_t e) const { return dirIrradiance_[d * elements_.size() + e]; }
  /// Outgoing radiance of the last iteration of element @p e on side @p side towards ±ω_k, W/(m² sr),
  /// all orders.
  const Color& outgoing(uint32_t e, int side) const { return outgoingTotal_[2 * size_t(e) + side]; }
  /// Lines traced by the last iteration (rays, including successive-hit continuations), summed
  /// over the ranks (the point lights' lines, traced by every rank, counted once).
  uint64_t lastRays() const { return rays_; }
  /// With several ranks: bytes this rank sent in the deposit exchanges since build(), and the
  /// seconds spent in them (waiting for the other ranks included).
  uint64_t exchangeBytes() const { return exchangeBytes_; }
  double exchangeSeconds() const { return exchangeSeconds_; }

 private:
  struct Deposit {
    uint32_t slot;  ///< 2·element + side
    Color value;
  };
  /// One exchange of the transfer: slot @c source's outgoing radiance (every order) arrives at slot @c target.
  struct Link {
    uint32_t target, source;  ///< 2·element + side
  };
  void traceDirectional(uint64_t seed);
  void computeOutgoing();
  /// Outgoing radiance of element @p e on side @p side towards @p w, per order, into @p out[0 .. orders_ − 1]
  /// (from the incoming state of the previous iteration).
  void outgoingOf(uint32_t e, int side, const Vec3& w, Color* out) const;
  void traceBundle(uint64_t seed);
  /// Traces rows 0 .. @p rows − 1 of a grid in parallel, this rank's rows only: @p row(a, out[a])
  /// appends row a's results to out[a] (emptied first) and returns the lines it traced. Then every
  /// rank receives the others' rows (shareChunks). Returns the lines of all ranks.
  template <typename T, typename Row>
  uint64_t traceRows(int rows, std::vector<std::vector<T>>& out, const Row& row);
  /// Several ranks: sends this rank's rows of @p chunks and its @p rays to every rank, fills in the
  /// other ranks' rows; returns the rays of all ranks. One rank: returns @p rays.
  template <typename T>
  uint64_t shareChunks(std::vector<std::vector<T>>& chunks, uint64_t rays);
  /// Sums the point lights' deposits into point_, times 1 / A_element.
  void gatherPoints();
  /// Sums the links of links_ in row order into incoming_ (every order), times @p scale / A_element.
  void gatherLinks(float scale);

  const RenderScene* scene_ = nullptr;
  BundleSettings settings_;
  Comm* comm_ = nullptr;
  uint64_t exchangeBytes_ = 0;
  double exchangeSeconds_ = 0;
  BundleElements elements_;
  std::vector<Color> sideIrradiance_;  ///< first-shot, 2 per patch (FirstShotTable::sideIrradiance)
  std::vector<uint32_t> points_;       ///< kept point and spot lights (LightSet indices)
  std::vector<uint32_t> directional_;  ///< kept directional lights
  int orders_ = 1;
  bool lumped_ = true;
  /// Per slot (2·element + side) and order b: incoming_[slot·orders_ + b], outgoing_ likewise.
  /// computeOutgoing() reads incoming_ as the previous iteration's state before the links overwrite it.
  std::vector<Color> incoming_, outgoing_;
  std::vector<Color> outgoingTotal_;  ///< per slot: Σ over the orders
  std::vector<Color> point_, prevPoint_, dirIrradiance_;
  Vec3 dir_{0.0f, 0.0f, 1.0f}, prevDir_{0.0f, 0.0f, 1.0f};
  uint64_t done_ = 0, rays_ = 0;
  std::vector<std::vector<Deposit>> chunks_;  ///< per grid row: the directional lights' deposits
  std::vector<std::vector<Link>> links_;      ///< per grid row: the transfer's exchanges
  std::vector<Deposit> pointDeposits_;        ///< the point lights' lines
};

}  // namespace firstshot
