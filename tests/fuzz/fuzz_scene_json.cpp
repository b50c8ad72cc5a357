// libFuzzer target fuzz_scene_json: a JSON scene (parse, validate, hash), as the tools load it (tests/fuzz/entry_points.h).
#include "tests/fuzz/entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return firstshot::fuzz::runOne(firstshot::fuzz::sceneJson, data, size);
}
