// libFuzzer target fuzz_mesh_import: an OBJ, PLY, glTF or GLB file through assimp, as the tools load it (tests/fuzz/entry_points.h).
#include "tests/fuzz/entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return firstshot::fuzz::runOne(firstshot::fuzz::meshImport, data, size);
}
