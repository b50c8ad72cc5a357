#pragma once
/// @file spot_integral.h
/// U_ij of a spot light (cone or IES table): the unoccluded integral of its kernel over a patch,
/// which has no closed form (the profile is a smoothstep in cos θ, or a table). The preprocessor's analytic estimator writes
/// r_ij = (1/∫profile)·V_ij·U_ij/A_j with this U (preprocess/sample_shot.cpp), and the renderer
/// recovers V_ij = r_ij·A_j·∫profile/U_ij with the same function (render/firstshot/lighting.cpp), so both
/// stages agree to the float rounding of r_ij.
#include "common/lights/emission_profile.h"
#include "common/patches/patches.h"
#include "common/table/firstshot.h"

namespace firstshot {

/// ∫ cosθ_x · profile(ω) / d² dA over patch @p p on side @p side (0: its normal's side, 1: the
/// other), in sr: the spot sample @p s (its position) with emission profile @p profile, ω the
/// direction from the light to the point.
/// Midpoint rule on an m × m grid per fan triangle, m = 32 within 2 patch diameters of the sample,
/// 12 within 8, 4 beyond (where the kernel is nearly linear across the patch); double precision.
double spotPatchIntegral(const LightSample& s, const EmissionProfile& profile, const Patch& p, int side);

}  // namespace firstshot
