// firstshot-render's integrator options (render/cli/integrator_options.h, render/integrators/integrator_cli.h):
// every integrator accepts the options it reads and refuses, with exit code 2 and the option's
// name, every other integrator's option (docs/cli.md, "Which integrator reads which option").
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "render/integrators/integrator.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;

/// Each option the integrators do not all share, with a valid value ("" for a flag; DIR: a temporary folder).
const std::vector<std::pair<std::string, std::string>> kOptions = {
    {"--primary", "patch"},         {"--light-sampler", "all"},      {"--patch-nee", "first"},
    {"--light-visibility", "off"},  {"--table-visibility", "off"},   {"--shoot-firstshot", "off"},
    {"--light-paths", "2"},         {"--accuracy", "0.5"},           {"--ic-samples", "16"},
    {"--bounces", "1"},             {"--ambient", "0.1"},            {"--gradients", "off"},
    {"--clamp-footprint", "1,50"},  {"--neighbour-clamp", "off"},    {"--ic-patch-nee", "1"},
    {"--two-pass", ""},             {"--one-pass", ""},              {"--cache-file", "DIR/c.fsic"},
    {"--show-records", "DIR/r.png"}, {"--iterations", "1"},          {"--bundle-resolution", "8"},
    {"--bundle-directions", "halton"}, {"--luminaires", "off"},
};

/// Which integrator reads which of them: the table of docs/cli.md.
const std::map<std::string, std::vector<std::string>> kUses = {
    {"path", {"--primary", "--light-sampler", "--patch-nee", "--light-visibility", "--table-visibility", "--luminaires"}},
    {"irradiance-cache", {"--primary", "--light-sampler", "--patch-nee", "--light-visibility", "--table-visibility",
                          "--accuracy", "--ic-samples", "--bounces", "--ambient", "--gradients", "--clamp-footprint",
                          "--neighbour-clamp", "--ic-patch-nee", "--two-pass", "--one-pass", "--cache-file",
                          "--show-records", "--luminaires"}},
    {"light", {"--primary", "--light-sampler", "--patch-nee", "--light-visibility", "--table-visibility",
               "--shoot-firstshot", "--light-paths", "--luminaires"}},
    {"bundle", {"--primary", "--table-visibility", "--iterations", "--bundle-resolution", "--bundle-directions"}},
    {"bdpt", {"--light-sampler", "--light-visibility", "--table-visibility", "--shoot-firstshot", "--luminaires"}},
};

bool uses(const std::string& integrator, const std::string& option) {
  const auto& u = kUses.at(integrator);
  return std::find(u.begin(), u.end(), option) != u.end();
}

/// The command line of @p integrator with @p option, writing into @p dir.
std::string command(const std::string& integrator, const std::string& option, std::string value, const std::string& dir) {
  if (const auto at = value.find("DIR"); at != std::string::npos) value.replace(at, 3, dir);
  std::string cmd = kRender + " " + firstshot::test::source("scenes/cornell.json") + " --integrator " + integrator +
                    " --width 8 --height 6 -q -o " + dir + "/out.exr " + option + " " + value;
  if (option != "--iterations") cmd += " --spp 1";
  if (integrator == "bundle" && option != "--bundle-resolution") cmd += " --bundle-resolution 8";
  return cmd;
}

}  // namespace

TEST(IntegratorOptionsCli, TheTableNamesEveryIntegrator) {
  for (const std::string& name : firstshot::integratorNames()) EXPECT_TRUE(kUses.count(name)) << name;
  EXPECT_EQ(kUses.size(), firstshot::integratorNames().size());
}

TEST(IntegratorOptionsCli, EachIntegratorRefusesTheOptionsItDoesNotRead) {
  const std::string dir = firstshot::test::tempDir();
  for (const auto& [integrator, used] : kUses)
    for (const auto& [option, value] : kOptions) {
      if (uses(integrator, option)) continue;
      SCOPED_TRACE(integrator + " " + option);
      const auto r = firstshot::test::run(command(integrator, option, value, dir));
      EXPECT_EQ(r.exitCode, 2) << r.output;
      EXPECT_THAT(r.output, HasSubstr("error: " + option + ": not used by --integrator " + integrator + " (used by: "));
    }
}

TEST(IntegratorOptionsCli, TheMessageListsTheIntegratorsThatReadIt) {
  const std::string dir = firstshot::test::tempDir();
  const auto r = firstshot::test::run(command("path", "--shoot-firstshot", "off", dir));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("error: --shoot-firstshot: not used by --integrator path (used by: light, bdpt)"));
}

TEST(IntegratorOptionsCli, EachIntegratorAcceptsTheOptionsItReads) {
  const std::string dir = firstshot::test::tempDir();
  for (const auto& [integrator, used] : kUses)
    for (const auto& [option, value] : kOptions) {
      if (!uses(integrator, option)) continue;
      SCOPED_TRACE(integrator + " " + option);
      const auto r = firstshot::test::run(command(integrator, option, value, dir));
      EXPECT_EQ(r.exitCode, 0) << r.output;
    }
}
