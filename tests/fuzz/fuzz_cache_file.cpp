// libFuzzer target fuzz_cache_file: an irradiance cache file (.fsic), as the tools load it (tests/fuzz/entry_points.h).
#include "tests/fuzz/entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return firstshot::fuzz::runOne(firstshot::fuzz::cacheFile, data, size);
}
