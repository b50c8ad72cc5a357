// The preprocessor split over ranks (common/util/comm.h), simulated by threads: the table every rank
// ends with equals one process's, byte for byte.
#include <gtest/gtest.h>

#include <mutex>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "preprocess/preprocessor.h"
#include "tests/test_util.h"
#include "tests/thread_comm.h"

namespace firstshot {
namespace {

std::string tableBytes(const FirstShotTable& t) {
  const std::string path = test::tempDir() + "/t.fsd";
  writeFirstShot(path, t);
  return test::readFile(path);
}

// Cornell (one area light cut into vertices, adaptive refinement passes re-shooting split patches)
// at a coarse resolution, with the Embree back end (no GL context per thread rank).
TEST(MpiPreprocess, TableIsTheSameForOneTwoAndThreeRanks) {
  const SceneDesc scene = loadScene(test::source("scenes/cornell.json"));
  PreprocessOptions o = defaultOptions(scene);
  o.settings.resolution = 64;
  o.settings.backend = "embree";
  o.quiet = true;
  o.threads = 1;
  PreprocessStats serialStats;
  const std::string serial = tableBytes(preprocessScene(scene, o, &serialStats));
  for (int ranks : {2, 3}) {
    std::vector<std::string> tables(static_cast<size_t>(ranks));
    std::vector<uint64_t> sent(static_cast<size_t>(ranks));
    test::runRanks(ranks, [&](Comm& comm) {
      PreprocessOptions mine = o;
      mine.comm = &comm;
      PreprocessStats st;
      const FirstShotTable t = preprocessScene(scene, mine, &st);
      static std::mutex m;
      std::lock_guard lock(m);
      tables[size_t(comm.rank())] = tableBytes(t);
      sent[size_t(comm.rank())] = st.bytesSent;
    });
    for (int r = 0; r < ranks; ++r) {
      EXPECT_EQ(tables[size_t(r)], serial) << ranks << " ranks, rank " << r;
      EXPECT_GT(sent[size_t(r)], 0u) << "rank " << r << " sent nothing";
    }
  }
  EXPECT_GT(serialStats.lightSamples, 8u);
  EXPECT_EQ(serialStats.bytesSent, 0u);
}

}  // namespace
}  // namespace firstshot
