#pragma once
/// @file film_exchange.h
/// Bringing the pixels the MPI ranks rendered into rank 0's film (common/util/comm.h): each rank renders
/// whole pixels (every sample of a pixel on one rank, in sample order), so copying its pixels'
/// accumulators gives rank 0 the film one process makes, bit for bit.
#include <vector>

#include "common/util/comm.h"
#include "render/output/film.h"

namespace firstshot {

/// A rectangle of pixels [x0, x1) × [y0, y1).
struct PixelRect {
  int x0, y0, x1, y1;
};

/// Sends the accumulators of the pixels in @p mine (this rank's) to rank 0, which copies every
/// rank's into @p film. Collective; nothing happens with one rank.
/// @throws std::runtime_error if a received rectangle lies outside the film.
void collectFilm(Comm& comm, Film& film, const std::vector<PixelRect>& mine);

}  // namespace firstshot
