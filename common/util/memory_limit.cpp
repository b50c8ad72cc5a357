// Input-sized allocations checked against the physical memory.
#include "common/util/memory_limit.h"

#include <fmt/core.h>
#include <unistd.h>

#include "common/util/error.h"

namespace firstshot {

uint64_t physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  return pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 0;
}

void requireMemory(double bytes, const std::string& file, const std::string& element, const std::string& what,
                   const std::string& hint) {
  const uint64_t available = physicalMemoryBytes();
  if (available == 0 || bytes <= double(available)) return;
  throw InputError(file, element,
                   fmt::format("needs {:.3g} GB for {}, more than this machine's {:.3g} GB of memory; {}", bytes * 1e-9,
                               what, double(available) * 1e-9, hint));
}

}  // namespace firstshot
