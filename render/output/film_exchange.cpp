// Rank 0 receives the pixels the other ranks rendered.
#include "render/output/film_exchange.h"

#include <stdexcept>

namespace firstshot {

void collectFilm(Comm& comm, Film& film, const std::vector<PixelRect>& mine) {
  if (comm.size() == 1) return;
  ByteWriter out;
  if (!comm.root()) {
    out.put<uint64_t>(mine.size());
    for (const PixelRect& r : mine) {
      out.put(r);
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) out.put(film.pixelSums(x, y));
    }
  }
  const std::vector<Bytes> all = comm.gather(out.bytes());
  for (size_t rank = 1; rank < all.size(); ++rank) {
    ByteReader in(all[rank]);
    for (uint64_t n = in.get<uint64_t>(); n > 0; --n) {
      const PixelRect r = in.get<PixelRect>();
      if (r.x0 < 0 || r.y0 < 0 || r.x1 > film.width() || r.y1 > film.height() || r.x0 > r.x1 || r.y0 > r.y1)
        throw std::runtime_error("exchange between ranks: pixels outside the image");
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) film.setPixelSums(x, y, in.get<Film::PixelSums>());
    }
  }
}

}  // namespace firstshot
