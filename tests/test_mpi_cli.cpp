// The -mpi tools under mpirun (built with -DFIRSTSHOT_MPI=ON only): the .fsd and the images of 1, 2
// and 3 ranks equal the MPI-free tools' outputs bit for bit (docs/mpi.md), and a failing job exits
// with its code and one message.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "render/output/film.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

// Root in a container: Open MPI refuses to start without these (harmless otherwise).
const std::string kMpirun = std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") + FIRSTSHOT_MPIEXEC +
                            " --oversubscribe --bind-to none -np ";

std::vector<float> pixels(const std::string& path) {
  int w = 0, h = 0;
  std::vector<std::string> channels;
  return Film::read(path, w, h, channels);
}

/// Runs @p command, expecting exit code 0.
void ok(const std::string& command) {
  const test::CommandResult r = test::run(command);
  ASSERT_EQ(r.exitCode, 0) << command << "\n" << r.output;
}

class MpiCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(test::tempDir());
    ok(std::string(FIRSTSHOT_PREPROCESS_EXE) + " " + test::source("scenes/cornell.json") + " -q --resolution 64 -o " +
       *dir_ + "/serial.fsd");
  }
  static std::string* dir_;
};
std::string* MpiCli::dir_ = nullptr;

// The GL back end (one OSMesa context per rank) and the Embree one, adaptive refinement included.
TEST_F(MpiCli, PreprocessWritesTheSameFsdForOneTwoAndThreeRanks) {
  const std::string& dir = *dir_;
  for (const char* backend : {"gl", "embree"}) {
    const std::string serial = dir + "/serial-" + backend + ".fsd";
    const std::string args = std::string(" ") + test::source("scenes/cornell.json") + " -q --resolution 64 --backend " + backend;
    ok(std::string(FIRSTSHOT_PREPROCESS_EXE) + args + " -o " + serial);
    for (int n : {1, 2, 3}) {
      const std::string out = dir + "/mpi" + std::to_string(n) + "-" + backend + ".fsd";
      ok(kMpirun + std::to_string(n) + " " + FIRSTSHOT_PREPROCESS_MPI_EXE + args + " --threads 1 -o " + out);
      EXPECT_EQ(test::readFile(out), test::readFile(serial)) << backend << ", " << n << " ranks";
    }
  }
}

// Every integrator: the same pixels (EXR values compared exactly) for 1, 2 and 3 ranks, with the default
// sampler (sobol: its per-pixel sequences must not depend on which rank renders a tile).
TEST_F(MpiCli, RenderGivesTheSameImageForOneTwoAndThreeRanks) {
  const std::string& dir = *dir_;
  const std::string base = " " + test::source("scenes/cornell.json") + " --firstshot " + dir + "/serial.fsd" +
                           " -q --width 40 --height 32 --spp 3";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"path", ""},
      {"irradiance-cache", " --ic-samples 64"},
      {"light", ""},
      {"bdpt", ""},
      {"bundle", " --bundle-resolution 48"},
  };
  for (const auto& [integrator, extra] : cases) {
    const std::string args = base + " --integrator " + integrator + extra;
    const std::string serial = dir + "/" + integrator + ".exr";
    ok(std::string(FIRSTSHOT_RENDER_EXE) + args + " -o " + serial);
    const std::vector<float> expected = pixels(serial);
    ASSERT_FALSE(expected.empty());
    for (int n : {1, 2, 3}) {
      const std::string out = dir + "/" + integrator + "-" + std::to_string(n) + ".exr";
      ok(kMpirun + std::to_string(n) + " " + FIRSTSHOT_RENDER_MPI_EXE + args + " --threads 1 -o " + out);
      EXPECT_TRUE(pixels(out) == expected) << integrator << ", " << n << " ranks";
    }
  }
}

// Bad input every rank meets: exit code 2 and one message (rank 0's), no output.
TEST_F(MpiCli, BadInputStopsTheJobWithExitCode2AndOneMessage) {
  const std::string out = *dir_ + "/bad.exr";
  const test::CommandResult r = test::run(kMpirun + "2 " + FIRSTSHOT_RENDER_MPI_EXE + " " + *dir_ + "/missing.json -q -o " + out);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("(rank 1 of 2)"), std::string::npos) << "rank 1 printed too:\n" << r.output;
  EXPECT_FALSE(std::ifstream(out).good());
  // An option that is not split over ranks is refused by name.
  const test::CommandResult s = test::run(kMpirun + "2 " + FIRSTSHOT_RENDER_MPI_EXE + " " + test::source("scenes/cornell.json") +
                                          " --checkpoint 10 -o " + *dir_ + "/c.exr");
  EXPECT_EQ(s.exitCode, 2) << s.output;
  EXPECT_NE(s.output.find("--checkpoint"), std::string::npos) << s.output;
}

// A failure one rank alone meets (here: its own scene path, through mpirun's MPMD syntax) stops the job
// with that rank's message and exit code while rank 0 waits in an exchange; nothing is written.
TEST_F(MpiCli, OneFailingRankStopsTheJobWithItsMessage) {
  const std::string out = *dir_ + "/one.exr";
  const std::string args = " --firstshot " + *dir_ + "/serial.fsd -q --width 32 --height 32 --spp 16 --threads 1 -o " + out;
  const test::CommandResult r = test::run(kMpirun + "1 " + FIRSTSHOT_RENDER_MPI_EXE + " " + test::source("scenes/cornell.json") +
                                          args + " : -np 1 " + FIRSTSHOT_RENDER_MPI_EXE + " " + *dir_ + "/only-rank-1.json" + args);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("(rank 1 of 2): error: " + *dir_ + "/only-rank-1.json"), std::string::npos) << r.output;
  EXPECT_FALSE(std::ifstream(out).good());
}

// Sensors (a work plane of 36 points) with the path tracer and with the irradiance cache, whose fill
// from the sensors' rays is split too: the same CSV bytes for 1, 2 and 3 ranks.
TEST_F(MpiCli, SensorsGiveTheSameResultsForOneTwoAndThreeRanks) {
  const std::string& dir = *dir_;
  for (const std::string integrator : {"path", "irradiance-cache"}) {
    const std::string args = " " + test::source("scenes/cornell.json") + " --firstshot " + dir + "/serial.fsd" +
                             " -q --grid 0.05,0.05,0.5,0.5,0.2,0.08 --samples 16 --integrator " + integrator +
                             (integrator == "path" ? "" : " --ic-samples 64");
    const std::string serial = dir + "/sensors-" + integrator + ".csv";
    ok(std::string(FIRSTSHOT_RENDER_EXE) + args + " -o " + serial);
    for (int n : {1, 2, 3}) {
      const std::string out = dir + "/sensors-" + integrator + "-" + std::to_string(n) + ".csv";
      ok(kMpirun + std::to_string(n) + " " + FIRSTSHOT_RENDER_MPI_EXE + args + " --threads 1 -o " + out);
      EXPECT_EQ(test::readFile(out), test::readFile(serial)) << integrator << ", " << n << " ranks";
    }
  }
}

}  // namespace
}  // namespace firstshot
