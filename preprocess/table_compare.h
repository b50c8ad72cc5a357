#pragma once
/// @file table_compare.h
/// How far two first-shot tables of one scene differ (e.g. the GL item buffers on a GPU against llvmpipe),
/// for firstshot-fsd-compare and bench/gpu_preprocess.sh. The rasterisers may differ in pixels along edges, and the
/// adaptive mesh may then split a patch in one table and not the other; so the tables are compared by what does
/// not depend on the mesh, the flux each light sample delivers, and factor by factor where the meshes agree.
#include <cstddef>
#include <cstdint>

#include "common/table/firstshot.h"

namespace firstshot {

struct TableDifference {
  bool sameSamples = false;  ///< the same number of light samples at the same positions
  bool sameMesh = false;     ///< the same patches (patch hash)
  /// Per light sample i its delivered flux per unit emission, Φ_i = Σ_j A_j r_ij (m²): the largest
  /// |Φ_i(test) − Φ_i(ref)| / Φ_i(ref) over the samples with Φ_i(ref) > 1e-6 max_i Φ_i(ref), and the
  /// same for Σ_i Φ_i.
  double maxSampleFlux = 0, totalFlux = 0;
  /// With the same mesh: Σ_ij A_j |Δr_ij| / Σ_ij A_j r_ij(ref) (a factor missing on one side counts whole),
  /// the number of (patch, sample) pairs whose factors are not bit-identical, and the largest |Δr|/r.
  double weightedL1 = 0, maxFactor = 0;
  size_t differingFactors = 0;
};

/// Compares @p test against @p ref (see TableDifference).
TableDifference compareTables(const FirstShotTable& ref, const FirstShotTable& test);

}  // namespace firstshot
