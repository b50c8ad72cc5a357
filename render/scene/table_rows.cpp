// A first-shot table's factors by patch (table_rows.h).
#include "render/scene/table_rows.h"

namespace firstshot {

const char* TableRows::check(const FirstShotTable& t) {
  const uint32_t n = t.mesh.size();
  if (t.rowStart.size() != size_t(n) + 1 || t.rowStart.front() != 0 || t.rowStart.back() != t.factor.size() ||
      t.sampleIndex.size() != t.factor.size())
    return "table sizes do not match the patch count";
  for (size_t j = 0; j < n; ++j)
    if (t.rowStart[j] > t.rowStart[j + 1]) return "row starts are not increasing";
  for (uint32_t i : t.sampleIndex)
    if (i >= t.samples.size()) return "a factor refers to a light sample that does not exist";
  return nullptr;
}

}  // namespace firstshot
