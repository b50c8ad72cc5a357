#include "preprocess/profile.h"

#include <cstdlib>
#include <cstring>

namespace firstshot::profile {
namespace {
std::atomic<int64_t> counters[Count];
}

bool enabled() {
  static const bool on = [] {
    const char* v = std::getenv("FIRSTSHOT_PROFILE");
    return v && *v && std::strcmp(v, "0") != 0;
  }();
  return on;
}

void add(Phase p, int64_t nanoseconds) { counters[p].fetch_add(nanoseconds, std::memory_order_relaxed); }

int64_t total(Phase p) { return counters[p].load(std::memory_order_relaxed); }

void report(std::FILE* out) {
  int64_t sum = 0;
  for (int p = 0; p < Count; ++p) sum += total(Phase(p));
  std::fprintf(out, "profile (thread-seconds):\n");
  for (int p = 0; p < Count; ++p)
    std::fprintf(out, "  %-42s %8.4f s %5.1f%%\n", name(Phase(p)), total(Phase(p)) * 1e-9,
                 sum > 0 ? 100.0 * double(total(Phase(p))) / double(sum) : 0.0);
  std::fprintf(out, "  %-42s %8.4f s\n", "sum", sum * 1e-9);
}

}  // namespace firstshot::profile
