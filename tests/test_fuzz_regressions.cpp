// The fuzz targets' inputs replayed in the normal build, through the same entry points
// (tests/fuzz/entry_points.h; docs/robustness.md, "Fuzzing"):
//  - every saved finding (tests/fuzz/regressions/<target>/*) ends in a clean firstshot::InputError, not a crash,
//    or loads if its name says ".loads." (a file the reader cannot tell from a valid one: the crash was
//    in how it was read; e.g. a light index that only the scene can refute);
//  - every seed (tests/fuzz/corpus/<target>/*) still loads, so the corpora keep starting from valid files.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "common/util/error.h"
#include "tests/fuzz/entry_points.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

struct FuzzInput {
  std::string target;  ///< the folder name: scene_json, mesh_import, fsd, cache_file
  std::string path;
};

void PrintTo(const FuzzInput& in, std::ostream* os) { *os << in.path; }

/// Every file under @p folder/<target>/, sorted.
std::vector<FuzzInput> inputsUnder(const std::string& folder) {
  std::vector<FuzzInput> inputs;
  for (const auto& dir : std::filesystem::directory_iterator(test::source(folder)))
    for (const auto& file : std::filesystem::directory_iterator(dir.path()))
      inputs.push_back({dir.path().filename().string(), file.path().string()});
  std::sort(inputs.begin(), inputs.end(), [](const FuzzInput& a, const FuzzInput& b) { return a.path < b.path; });
  return inputs;
}

std::string readBytes(const std::string& path) { return test::readFile(path); }

std::string testName(const testing::TestParamInfo<FuzzInput>& info) {
  std::string name = info.param.target + "_" + std::filesystem::path(info.param.path).filename().string();
  std::replace_if(name.begin(), name.end(), [](unsigned char c) { return !std::isalnum(c); }, '_');
  return name;
}

class FuzzFinding : public testing::TestWithParam<FuzzInput> {};
class FuzzSeed : public testing::TestWithParam<FuzzInput> {};

TEST_P(FuzzFinding, EndsInAnInputErrorOrLoads) {
  const fuzz::EntryPoint f = fuzz::entryPoint(GetParam().target);
  ASSERT_NE(f, nullptr) << "unknown fuzz target folder " << GetParam().target;
  if (GetParam().path.find(".loads.") != std::string::npos)
    EXPECT_NO_THROW(f(readBytes(GetParam().path)));
  else
    EXPECT_THROW(f(readBytes(GetParam().path)), InputError);
}

TEST_P(FuzzSeed, Loads) {
  const fuzz::EntryPoint f = fuzz::entryPoint(GetParam().target);
  ASSERT_NE(f, nullptr) << "unknown fuzz target folder " << GetParam().target;
  EXPECT_NO_THROW(f(readBytes(GetParam().path)));
}

INSTANTIATE_TEST_SUITE_P(Regressions, FuzzFinding, testing::ValuesIn(inputsUnder("tests/fuzz/regressions")), testName);
INSTANTIATE_TEST_SUITE_P(Corpus, FuzzSeed, testing::ValuesIn(inputsUnder("tests/fuzz/corpus")), testName);

}  // namespace
}  // namespace firstshot
