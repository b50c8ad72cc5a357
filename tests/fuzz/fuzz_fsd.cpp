// libFuzzer target fuzz_fsd: a first-shot table (.fsd), as the tools load it (tests/fuzz/entry_points.h).
#include "tests/fuzz/entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return firstshot::fuzz::runOne(firstshot::fuzz::firstShotFile, data, size);
}
