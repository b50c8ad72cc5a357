// libFuzzer target fuzz_scene_xml: a Mitsuba 3 XML scene (parse, validate, hash), as the tools load it (tests/fuzz/entry_points.h).
#include "tests/fuzz/entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return firstshot::fuzz::runOne(firstshot::fuzz::sceneXml, data, size);
}
