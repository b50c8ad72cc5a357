// The table's luminaires seen by the renderer (luminaires.h).
#include "render/lights/luminaires.h"

#include <algorithm>

#include "render/lights/lights.h"

namespace fs {

LuminaireBoxes::LuminaireBoxes(const std::vector<Luminaire>* luminaires, const LightSet& lights)
    : items_(luminaires) {
  if (empty()) return;
  lightLuminaire_.assign(lights.lights().size(), -1);
  for (size_t l = 0; l < lights.lights().size(); ++l) {
    const uint32_t s = lights.lights()[l].sceneIndex;
    for (size_t i = 0; i < items_->size(); ++i) {
      const std::vector<uint32_t>& ls = (*items_)[i].lights;
      if (std::binary_search(ls.begin(), ls.end(), s)) lightLuminaire_[l] = int(i);
    }
  }
  exitFirst_.assign(items_->size() + 1, 0);
  for (size_t i = 0; i < items_->size(); ++i) exitFirst_[i + 1] = exitFirst_[i] + (*items_)[i].patchCount();
}

int LuminaireBoxes::containing(const Vec3& p) const {
  if (empty()) return -1;
  for (size_t i = 0; i < items_->size(); ++i)
    if ((*items_)[i].contains(p)) return int(i);
  return -1;
}

int LuminaireBoxes::entries(const Vec3& o, const Vec3& d, float tmax, Entry* out) const {
  if (empty()) return 0;
  int n = 0;
  for (size_t i = 0; i < items_->size() && n < kMaxEntries; ++i) {
    Entry e;
    if (!(*items_)[i].entry(o, d, tmax, e.t, e.face)) continue;
    e.luminaire = uint32_t(i);
    int k = n++;
    for (; k > 0 && out[k - 1].t > e.t; --k) out[k] = out[k - 1];  // nearest first
    out[k] = e;
  }
  return n;
}

uint32_t LuminaireBoxes::exitLuminaire(uint32_t e) const {
  return uint32_t(std::upper_bound(exitFirst_.begin(), exitFirst_.end(), e) - exitFirst_.begin()) - 1;
}

}  // namespace fs
