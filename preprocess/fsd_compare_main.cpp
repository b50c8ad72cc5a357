// firstshot-fsd-compare: how far a first-shot table differs from a reference table of the same scene
// (preprocess/table_compare.h); exit 0 when they agree within the tolerance, 1 when not, 2 for bad input.
//   firstshot-fsd-compare REF.fsd TEST.fsd [--tolerance T]
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "common/table/firstshot.h"
#include "common/util/cli.h"
#include "common/util/error.h"
#include "preprocess/table_compare.h"

int main(int argc, char** argv) {
  return firstshot::runTool("firstshot-fsd-compare", [&] {
    CLI::App app{"firstshot-fsd-compare: compares a first-shot table (.fsd) with a reference table of the same scene"};
    std::string refPath, testPath;
    double tolerance = 1e-3;
    app.add_option("reference", refPath, "the reference table (.fsd)")->required();
    app.add_option("test", testPath, "the table to compare (.fsd)")->required();
    app.add_option("--tolerance", tolerance, "agree: the same light samples, and every sample's delivered flux "
                                             "(Σ_j A_j r_ij) within this relative difference (default 1e-3)")
        ->check(CLI::NonNegativeNumber);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app.exit(e) == 0 ? 0 : firstshot::kExitBadInput;
    }
    const firstshot::FirstShotTable ref = firstshot::readFirstShot(refPath), test = firstshot::readFirstShot(testPath);
    const firstshot::TableDifference d = firstshot::compareTables(ref, test);
    const bool agree = d.sameSamples && d.maxSampleFlux <= tolerance;
    fmt::print("{}: patches {} / {}, factors {} / {}, {}; sample flux max rel. diff {:.3g}, total {:.3g}", agree ? "agree" : "DIFFER",
               ref.mesh.size(), test.mesh.size(), ref.nonZeros(), test.nonZeros(),
               !d.sameSamples ? "other light samples" : d.sameMesh ? "same mesh" : "other mesh", d.maxSampleFlux, d.totalFlux);
    if (d.sameMesh) fmt::print("; factors: {} differ, weighted L1 {:.3g}, max rel. {:.3g}", d.differingFactors, d.weightedL1, d.maxFactor);
    fmt::print("\n");
    return agree ? 0 : 1;
  });
}
