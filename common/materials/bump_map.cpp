// OBJ/MTL bump maps as normal maps (common/materials/bump_map.h).
#include "common/materials/bump_map.h"

#include <cmath>
#include <utility>

namespace firstshot {

bool bumpImageIsNormalMap(const TexelImage& im) {
  const Color& m = im.mean;
  return m.z > 0.6f && std::abs(m.x - 0.5f) < 0.15f && std::abs(m.y - 0.5f) < 0.15f;
}

TexelImage normalMapFromHeights(const TexelImage& heights, float scale) {
  const int w = heights.width, h = heights.height;
  const auto at = [&](int x, int y) { return heights.at(((x % w) + w) % w, ((y % h) + h) % h).x; };
  std::vector<Color> texels(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float dx = 0.5f * (at(x + 1, y) - at(x - 1, y)), dy = 0.5f * (at(x, y + 1) - at(x, y - 1));
      const Vec3 n = glm::normalize(Vec3(-scale * dx, -scale * dy, 1.0f));
      texels[size_t(y) * size_t(w) + size_t(x)] = 0.5f * (n + Vec3(1.0f));
    }
  return makeTexelImage(w, h, std::move(texels), heights.name + " (heights as normals)");
}

}  // namespace firstshot
