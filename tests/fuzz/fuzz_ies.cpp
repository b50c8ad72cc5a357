// libFuzzer target fuzz_ies: an IES LM-63 photometric file, as an "ies" light loads it (tests/fuzz/entry_points.h).
#include "tests/fuzz/entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return firstshot::fuzz::runOne(firstshot::fuzz::iesFile, data, size);
}
