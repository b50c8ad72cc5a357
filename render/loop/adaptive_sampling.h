#pragma once
/// @file adaptive_sampling.h
/// Adaptive sampling (RenderOptions::adaptive, `firstshot-render --adaptive`): after kAdaptiveBase uniform
/// passes the render goes in rounds, each giving every pixel one more sample and kAdaptiveExtras × (the
/// pixels) extra samples shared out in proportion to each pixel's estimated error
/// v_p / n_p (v_p: the variance of its neighbours' samples, the mean over R, G, B; n_p: its own samples;
/// pixelErrorWeight). The image's squared error
/// Σ v_p / n_p falls fastest that way, and the pixels' counts tend to n_p ∝ √v_p, the allocation that minimises
/// it for a given number of samples: a few pixels that hold most of the error (a filament seen through glass,
/// a light's highlight in a polished plate) take the samples they need, and the uniform sample of each round
/// keeps every pixel converging whatever its first samples said.
///
/// The targets are a function of the film's sums, the seed and the round only, summed tile by tile in tile
/// order (over every rank of an MPI run): the image is the same for any number of threads or ranks.
#include <cstdint>
#include <vector>

#include "common/util/comm.h"
#include "render/output/film.h"
#include "render/output/film_exchange.h"

namespace firstshot {

inline constexpr int kAdaptiveBase = 16;         ///< uniform passes before the first round
inline constexpr double kAdaptiveExtras = 1.0;   ///< a round's extra samples, per pixel of the image
inline constexpr uint32_t kAdaptiveMaxExtra = 64;  ///< at most this many extra samples per pixel and round

/// The mean over R, G, B of pixel (x, y)'s samples' variance (0 with fewer than 2 samples).
double pixelVariance(const Film& film, int x, int y);

/// The estimated squared error of pixel (x, y)'s mean: its neighbours' pixelVariance (the 8 around it within
/// @p rect, its tile) over its own samples. Not its own variance: a count that followed its own samples would bias
/// its mean (a rare bright sample would draw more samples that dilute it: the classroom's image came out 2–4%
/// dark), one that follows its neighbours' does not (their samples are independent of its own).
double pixelErrorWeight(const Film& film, const PixelRect& rect, int x, int y);

/// The sample counts every pixel of @p tiles (this rank's, with their indices @p tileIndex among all the
/// image's tiles) is to reach in round @p round: its count now + 1 + its share of @p extras samples by
/// pixelErrorWeight(), rounded by a dither of (@p seed, pixel, @p round) (so that the extras given add up
/// to @p extras on average), at most kAdaptiveMaxExtra. Row-major over the image; pixels of other ranks'
/// tiles are left 0. Collective over @p comm (the weights' sum).
std::vector<uint32_t> adaptiveTargets(const Film& film, const std::vector<PixelRect>& tiles,
                                      const std::vector<uint64_t>& tileIndex, Comm& comm, uint64_t seed, int round,
                                      double extras);

}  // namespace firstshot
