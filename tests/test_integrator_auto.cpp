// --integrator auto (render/loop/integrator_pilot.h, render/cli/render_command_auto.cpp): the pilot's size stays
// within its share of the budget, its choice does not depend on the threads, the
// options given narrow it, a table of luminaires alone adds no variants, on a bulb behind glass it hands the render
// to light tracing, with its table to the irradiance cache (whose fill is charged at its share of the render), and a
// table that does not pay is left unread (the render, and its resumption, as without --firstshot).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/render_util.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using ::testing::StartsWith;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;

/// The lines of @p output from the pilot's table header to the choice (the figures and the choice).
std::string pilotTable(const std::string& output) {
  const auto from = output.find("  setting");
  const auto to = output.find("chose ");
  if (from == std::string::npos || to == std::string::npos) return "";
  return output.substr(from, output.find('\n', to) - from);
}

/// The setting --integrator auto chose, as printed ("light --shoot-firstshot off").
std::string choice(const std::string& output) {
  const std::string key = "--integrator auto chose ";
  const auto at = output.find(key);
  if (at == std::string::npos) return "";
  const auto end = output.find(" (efficiency", at);
  return output.substr(at + key.size(), end - at - key.size());
}

/// Writes the shipped scene @p source to @p to with its settings' 64 spp made 305, what --time 20 sizes at
/// 128 x 128 (the pilot's budget of such a render); false if it has no "spp": 64.
/// Renders @p base (a command without -o) to @p out with a checkpoint, stopped after its second pass, expecting the
/// pilot to choose @p chosen; resumed, the render takes the checkpoint's choice. @p resumed: the resumed run's output.
void expectTheCheckpointKeepsTheChoice(const std::string& base, const std::string& out, const std::string& chosen,
                                       std::string& resumed) {
  const auto stopped =
      firstshot::test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-2 " + base + " --spp 305 --checkpoint 1000 -o " + out);
  ASSERT_EQ(stopped.exitCode, 130) << stopped.output;
  ASSERT_EQ(choice(stopped.output), chosen) << stopped.output;
  const auto run = firstshot::test::run(base + " --spp 3 --resume -o " + out);
  resumed = run.output;
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("--integrator auto: " + chosen + " (the choice of the render in the checkpoint)"));
}

bool copyAt305Spp(const std::string& source, const std::string& to) {
  std::string text = firstshot::test::readFile(firstshot::test::source(source));
  const std::string from = "\"spp\": 64";
  const auto spp = text.find(from);
  if (spp == std::string::npos) return false;
  text.replace(spp, from.size(), "\"spp\": 305");
  std::ofstream(to) << text;
  return true;
}

/// --integrator auto on shipped scene @p source at 305 spp (copyAt305Spp), 128 x 128, two threads: its output.
firstshot::test::CommandResult autoAt305Spp(const std::string& source) {
  const std::string dir = firstshot::test::tempDir(), scene = dir + "/scene.json";
  if (!copyAt305Spp(source, scene)) return {-1, source + " has no \"spp\": 64 to raise"};
  return firstshot::test::run(kRender + " " + scene + " --width 128 --height 128 --time 0.01 --threads 2 -o " + dir + "/a.exr");
}

/// firstshot-preprocess at its defaults: @p scene's table written to @p fsd.
auto preprocess(const std::string& scene, const std::string& fsd) {
  return firstshot::test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " " + scene + " --quiet -o " + fsd);
}

/// The figure @p back places from the end of @p setting's row in the pilot's table (0: the render's projected error,
/// 1: the efficiency, 2: the Mrays per image); -1 if it has none.
double figure(const std::string& output, const std::string& setting, int back = 0) {
  const auto row = output.find("\n  " + setting + " ");
  if (row == std::string::npos) return -1.0;
  std::string line = output.substr(row + 1, output.find('\n', row + 1) - row - 1);
  if (line.size() > 2 && line.substr(line.size() - 2) == " *") line.resize(line.size() - 2);
  for (int k = 0; k < back; ++k) {
    line.erase(line.find_last_not_of(' ', line.find_last_of(' ')) + 1);
  }
  const auto last = line.find_last_of(' ');
  return last == std::string::npos ? -1.0 : std::atof(line.c_str() + last + 1);
}

/// The whole number printed right after @p key in @p output (the first time); -1 if @p key is absent.
int numberAfter(const std::string& output, const std::string& key) {
  const auto at = output.find(key);
  return at == std::string::npos ? -1 : std::atoi(output.c_str() + at + key.size());
}

/// The pilot's rays in percent of the render's, as it prints them; -1 if it did not.
double pilotShare(const std::string& output) {
  const auto share = output.find("% of the rays");
  return share == std::string::npos ? -1.0 : std::atof(output.c_str() + output.rfind('(', share) + 1);
}

/// The efficiency printed in the pilot's table for @p setting (its row's last figure but one); -1 if it has none.
double efficiency(const std::string& output, const std::string& setting) { return figure(output, setting, 1); }

}  // namespace

TEST(IntegratorAuto, TheChoiceIsTheSameForOneAndTwoThreads) {
  const std::string dir = firstshot::test::tempDir(), scene = firstshot::test::source("scenes/cornell.json");
  // --time: the pilot takes its size from the scene's 64 spp, the render itself one pass.
  const std::string base = kRender + " " + scene + " --width 64 --height 64 --time 0.001 --seed 7 -o " + dir + "/a.exr";
  const auto one = firstshot::test::run(base + " --threads 1");
  const auto two = firstshot::test::run(base + " --threads 2");
  ASSERT_EQ(one.exitCode, 0) << one.output;
  ASSERT_EQ(two.exitCode, 0) << two.output;
  ASSERT_FALSE(pilotTable(one.output).empty()) << one.output;
  EXPECT_EQ(pilotTable(one.output), pilotTable(two.output));  // every figure, digit for digit, and the choice
  for (const char* name : {"path", "irradiance-cache", "light", "bdpt"}) EXPECT_THAT(one.output, HasSubstr(name));
  // Another seed measures other noise.
  const auto other = firstshot::test::run(kRender + " " + scene + " --width 64 --height 64 --time 0.001 --seed 8 -o " + dir +
                                   "/b.exr");
  ASSERT_EQ(other.exitCode, 0) << other.output;
  EXPECT_NE(pilotTable(one.output), pilotTable(other.output));
}

TEST(IntegratorAuto, OptionsGivenNarrowTheChoice) {
  const std::string dir = firstshot::test::tempDir(), scene = firstshot::test::source("scenes/cornell.json");
  const auto r = firstshot::test::run(kRender + " " + scene + " --width 16 --height 16 --spp 2 --light-paths 2 -o " + dir + "/a.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--integrator auto: light (the only integrator that reads the options given)"));
  const auto small = firstshot::test::run(kRender + " " + scene + " --width 16 --height 16 --spp 2 -o " + dir + "/b.exr");
  ASSERT_EQ(small.exitCode, 0) << small.output;
  EXPECT_THAT(small.output, HasSubstr("--integrator auto: path (16 x 16 at 2 spp leaves no room for a pilot)"));
  const auto none = firstshot::test::run(kRender + " " + scene + " --width 16 --height 16 --spp 2 --light-paths 2 "
                                  "--accuracy 0.3 -o " + dir + "/c.exr");
  EXPECT_EQ(none.exitCode, 2) << none.output;
  EXPECT_THAT(none.output, HasSubstr("auto: no integrator reads all of"));
}

TEST(IntegratorAuto, ABulbBehindGlassGoesToLightTracing) {
  // No shadow ray passes the envelope: the path tracer and the cache find the filament only through BSDF samples
  // that refract into it, light tracing shoots from it (over 100x in the pilot). --time: the pilot takes its size
  // from the scene's 64 spp, the render one pass.
  const std::string dir = firstshot::test::tempDir(), scene = firstshot::test::source("scenes/glass-bulb-room.json");
  const auto r = firstshot::test::run(kRender + " " + scene + " --width 80 --height 60 --time 0.01 -o " + dir + "/a.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(choice(r.output), "light") << r.output;
}

TEST(IntegratorAuto, ResumeTakesTheCheckpointsChoice) {
  // The first render's --time sizes a pilot; the resumed one's would not: it takes the choice the checkpoint holds.
  const std::string dir = firstshot::test::tempDir(), scene = firstshot::test::source("scenes/cornell.json");
  const std::string base = kRender + " " + scene + " --width 64 --height 48 --threads 2";
  const auto stopped = firstshot::test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-2 " + base +
                                     " --time 100 --checkpoint 1000 -o " + dir + "/a.exr");
  ASSERT_EQ(stopped.exitCode, 130) << stopped.output;
  const std::string chosen = choice(stopped.output);
  ASSERT_FALSE(chosen.empty()) << stopped.output;
  const auto resumed = firstshot::test::run(base + " --time 0.2 --resume -o " + dir + "/a.exr");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("--integrator auto: " + chosen + " (the choice of the render in the checkpoint)"));
}

TEST(IntegratorAuto, ATableOfLuminairesAloneIsNotTriedTwice) {
  // A point light in a clear glass sphere is a luminaire: the table replaces no light, so --patch-nee and
  // --shoot-firstshot would change nothing, and the pilot tries each integrator once with the table (and the path
  // tracer and light tracing once more without it: light tracing with the table shoots the luminaire's exit light).
  // Without the glass the table replaces the light: the variants are tried, and light tracing without the table is
  // not (--shoot-firstshot off is the plain light tracer then).
  const std::string dir = firstshot::test::tempDir(), pre = FIRSTSHOT_PREPROCESS_EXE;
  for (const bool glass : {true, false}) {
    const std::string scene = dir + (glass ? "/bulb.json" : "/bare.json"), fsd = scene + ".fsd";
    std::ofstream(scene) << R"({"materials": {"floor": {"type": "diffuse", "albedo": 0.5},
        "glass": {"type": "dielectric", "ior": 1.5}},
      "shapes": [{"type": "quad", "material": "floor", "vertices": [[-2,0,-2],[-2,0,2],[2,0,2],[2,0,-2]]})"
                         << (glass ? R"(, {"type": "sphere", "material": "glass", "center": [0, 1, 0], "radius": 0.1})" : "")
                         << R"(],
      "lights": [{"type": "point", "position": [0, 1, 0], "power": 100}],
      "camera": {"position": [0, 1.5, 3], "look_at": [0, 0.5, 0], "fov_y": 50, "resolution": [64, 64]},
      "settings": {"patch_size": 0.5, "spp": 256}})";
    const auto p = firstshot::test::run(pre + " " + scene + " --luminaire-particles 65536 --quiet -o " + fsd);
    ASSERT_EQ(p.exitCode, 0) << p.output;
    const auto r = firstshot::test::run(kRender + " " + scene + " --firstshot " + fsd + " --time 0.001 -o " + dir + "/a.exr");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string table = pilotTable(r.output);
    ASSERT_FALSE(table.empty()) << r.output;
    EXPECT_EQ(table.find("--patch-nee") == std::string::npos, glass) << table;
    EXPECT_EQ(table.find("--shoot-firstshot") == std::string::npos, glass) << table;
    EXPECT_THAT(table, HasSubstr("\n  path, no table ")) << table;
    EXPECT_EQ(table.find("\n  light, no table ") != std::string::npos, glass) << table;  // with luminaires only
    EXPECT_EQ(table.find("cache, no table"), std::string::npos) << table;
  }
}

TEST(IntegratorAuto, EveryImageTakesAboutTheRaysOfTheFirsts) {
  // The Cornell box with its table, 128 x 128 at 305 spp (what --time 20 sizes): 48 x 48 at 6 spp for the path
  // tracer. Light tracing's two passes at its 8 light paths per pixel took 3.6x those rays (0.193 against 0.053
  // Mrays), the path tracer without the table 1.5x (its rays weighed as work against the readers' 1.5), and the pilot
  // 10.5-10.9% of the render's rays (7.1-7.5% with the images at equal rays, the cache's fills at 512 hemisphere rays
  // per record); the cache's fills and its four images are counted in its printed share, which is at most 5%.
  const std::string dir = firstshot::test::tempDir(), scene = dir + "/cornell.json";
  ASSERT_TRUE(copyAt305Spp("scenes/cornell.json", scene));
  ASSERT_EQ(preprocess(scene, dir + "/c.fsd").exitCode, 0);
  const auto r = firstshot::test::run(kRender + " " + scene + " --firstshot " + dir +
                                      "/c.fsd --width 128 --height 128 --time 0.01 --threads 2 -o " + dir + "/a.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const double path = figure(r.output, "path --patch-nee off", 2);
  ASSERT_GT(path, 0.0) << r.output;
  for (const char* s : {"light --shoot-firstshot patches", "light --shoot-firstshot off", "path, no table"})
    EXPECT_LT(figure(r.output, s, 2), 1.3 * path) << s << "\n" << r.output;
  EXPECT_LE(pilotShare(r.output), 5.0) << r.output;
  // The projected render error is √(1 / (efficiency · G)), G the same for all: error² × the efficiency relative to
  // the choice is the chosen one's error² (to the printed digits).
  const double chosen = figure(r.output, choice(r.output), 0);
  ASSERT_GT(chosen, 0.0) << r.output;
  for (const char* s : {"path --patch-nee off", "light --shoot-firstshot patches", "path, no table"}) {
    const double e = figure(r.output, s, 0), eff = figure(r.output, s, 1);
    ASSERT_GT(e, 0.0) << s << "\n" << r.output;
    EXPECT_NEAR(e * std::sqrt(eff), chosen, 0.02 * chosen + 1e-4) << s << "\n" << r.output;
  }
}

TEST(IntegratorAuto, ThePilotTakesAtMostFivePercentOfTheRendersRays) {
  // The many-lights room (64 lights), 128 x 128 at 305 spp: next-event estimation to every light takes about 27 times
  // the path tracer's rays per pass; at the two passes each image takes at least, the pilot took 9.0% of the render's
  // rays. A pass over a sixteenth of the pixels tells it is not worth trying, and the pilot stays within its 5%.
  const auto r = autoAt305Spp("scenes/many-lights.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, testing::ContainsRegex("  path --light-sampler all +- +- +- +[0-9.]+ \\(not tried: one pass "
                                               "takes [0-9.]+ times an image's rays\\)"));
  EXPECT_LE(pilotShare(r.output), 5.0) << r.output;
}

// The Ward sphere, 128 x 128 at 305 spp: the cache's fill at 12 x 12 takes 4 times an image's rays, and its two fills
// took the pilot to 7.2% of the render's rays. They must leave the pilot's share its images and the candidates' after
// it: the fill stops there and the cache is not measured (the path tracer is 1.5 times as efficient there).
TEST(IntegratorAuto, TheCachesFillsStopWhereThePilotWouldPassItsShare) {
  const auto r = autoAt305Spp("scenes/ward-sphere.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, testing::ContainsRegex("  irradiance-cache +- +- +- +[0-9.]+ \\(its preprocessing alone outgrows"));
  EXPECT_LE(pilotShare(r.output), 5.0) << r.output;
}

TEST(IntegratorAuto, TheCachesRaysSizedByThePilotAreKeptOnResume) {
  FIRSTSHOT_STATISTICS_ONLY("IntegratorPilot.TheRendersRecordsTakeTheRaysItsBudgetPaysFor");
  // McGuire's box as it ships (../shared/scenes, skipped where absent), 128 x 128 in 20 s: the pilot takes the cache,
  // its records gathered with more than the 512 rays of --ic-samples (1024 when measured: 0.0134 against the cache's
  // 0.0187 at 512, docs/measurements.md), the render's cache gathers with them, and the checkpoint's key keeps them.
  const std::string scene = firstshot::test::source("../shared/scenes/mcguire-cornell-box/CornellBox-Original.obj");
  if (!std::filesystem::exists(scene)) GTEST_SKIP() << scene << " is absent (the public scenes live in ../shared/scenes)";
  const std::string dir = firstshot::test::tempDir();
  const std::string base = kRender + " " + scene + " --width 128 --height 128 --seed 1 --threads 2 -o " + dir + "/a.exr";
  const auto stopped =
      firstshot::test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-1 " + base + " --time 20 --checkpoint 1000");
  ASSERT_EQ(stopped.exitCode, 130) << stopped.output;
  ASSERT_EQ(choice(stopped.output), "irradiance-cache") << stopped.output;
  const int rays = numberAfter(stopped.output, "  irradiance-cache: filled at 12 x 12; at ");
  ASSERT_GE(rays, 0) << stopped.output;
  EXPECT_GT(rays, 512) << stopped.output;
  const auto resumed = firstshot::test::run(base + " --time 1 --resume");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("irradiance-cache (the choice of the render in the checkpoint)"));
  EXPECT_THAT(resumed.output, HasSubstr(", " + std::to_string(rays) + " hemisphere rays per level-0 record"))
      << resumed.output;
}

TEST(IntegratorAuto, TheCacheNamedSizesItsRaysToTheTimeGiven) {
  FIRSTSHOT_STATISTICS_ONLY("IntegratorPilot.TheRendersRecordsTakeTheRaysItsBudgetPaysFor");
  // --integrator irradiance-cache with --time and no --ic-samples: a pilot of the cache alone sizes its records'
  // rays (the Cornell box at 48 x 48 in 8 s: 2048), the checkpoint keeps them, a resumed render takes them; with
  // --ic-samples given they are the option's.
  const std::string dir = firstshot::test::tempDir(), scene = firstshot::test::source("scenes/cornell.json");
  const std::string base = kRender + " " + scene + " --integrator irradiance-cache --width 48 --height 48 --seed 1 "
                           "--threads 2 -o " + dir + "/a.exr";
  const auto stopped =
      firstshot::test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-1 " + base + " --time 8 --checkpoint 1000");
  ASSERT_EQ(stopped.exitCode, 130) << stopped.output;
  const std::string says = "firstshot-render: irradiance-cache: ";
  const int rays = numberAfter(stopped.output, says);
  ASSERT_GE(rays, 0) << stopped.output;
  EXPECT_GT(rays, 512) << stopped.output;
  const auto resumed = firstshot::test::run(base + " --time 0.2 --resume");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr(", " + std::to_string(rays) + " hemisphere rays per level-0 record"));
  // A fill that would take the time stops at three quarters of it (--ic-samples 4096 at 128 x 128: a second or more;
  // 2 ms given).
  const auto cut = firstshot::test::run(kRender + " " + scene + " --integrator irradiance-cache --width 128 --height 128 "
                                        "--seed 1 --threads 2 --ic-samples 4096 --time 0.002 -o " + dir + "/c.exr");
  ASSERT_EQ(cut.exitCode, 0) << cut.output;
  EXPECT_THAT(cut.output, testing::ContainsRegex("the fill stopped at three quarters of the render's time after "
                                                 "[0-9]+ of 16384 pixels of sweep 1"));
  // Given, the option is the user's: no pilot.
  const auto fixed = firstshot::test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-1 " + base +
                                          " --time 8 --ic-samples 64 --checkpoint 1000");
  ASSERT_EQ(fixed.exitCode, 130) << fixed.output;
  EXPECT_EQ(fixed.output.find(says), std::string::npos) << fixed.output;
}

TEST(IntegratorAuto, ABulbBehindGlassWithItsTableGoesToTheCache) {
  // With the table the filament's light leaves the glass as the luminaire's exit light, which the cache samples at
  // every shaded point: its records' error is small, and its fill, charged at its share of the render (305 spp of
  // 128 x 96 pixels, what --time 20 sizes at 128 x 128; --time 0.01 stops the render after its fill), does not
  // decide. At the scene's 64 spp the fill outgrows the pilot (the test above); at 1024 spp of 64 x 48 the path
  // tracer's noise falls below the records' error (as the pilot measures it from records of 12 x 9 pixels).
  const std::string dir = firstshot::test::tempDir();
  std::string text = firstshot::test::readFile(firstshot::test::source("scenes/glass-bulb-room.json"));
  ASSERT_EQ(text.find("\"settings\""), std::string::npos);
  text.insert(text.find('{') + 1, "\"settings\": {\"spp\": 305},");
  const std::string scene = dir + "/bulb.json";
  std::ofstream(scene) << text;
  const auto p = preprocess(scene, dir + "/t.fsd");
  ASSERT_EQ(p.exitCode, 0) << p.output;
  const std::string base = kRender + " " + scene + " --firstshot " + dir + "/t.fsd --width 128 --height 96 --time 0.01";
  const auto r = firstshot::test::run(base + " --threads 2 -o " + dir + "/a.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(choice(r.output), "irradiance-cache") << r.output;
  EXPECT_THAT(r.output, HasSubstr("irradiance-cache: filled at 12 x 9")) << r.output;
#ifndef FIRSTSHOT_UNDER_SANITIZERS  // the same code on one thread: logic, not memory (the optimised build checks it)
  // The cache's fills and passes in the pilot do not depend on the threads either: every figure, digit for digit.
  const auto one = firstshot::test::run(base + " --threads 1 -o " + dir + "/b.exr");
  ASSERT_EQ(one.exitCode, 0) << one.output;
  EXPECT_EQ(pilotTable(one.output), pilotTable(r.output));
#endif
}

TEST(IntegratorAuto, ABowlLampWithItsTableGoesToTheCache) {
  FIRSTSHOT_STATISTICS_ONLY("IntegratorAuto.ABulbBehindGlassWithItsTableGoesToTheCache");
  // The shipped bowl-lamp room with its table, 128 x 128 with the 17 s that 20 s leave after its preprocessing: the
  // cache + table is 13x light tracing's efficiency there (docs/measurements.md). Its fill at 12 x 12 grown to the
  // render's picture in proportion to the pixels came out at 82-85% of the render's rays, about three times what it
  // takes, and light tracing won the pilot for seed 2; grown as pixels^0.8 it is 28%. Stopped after the render's
  // first pass (the pilot and the fill done).
  const std::string dir = firstshot::test::tempDir(), scene = firstshot::test::source("scenes/bowl-lamp-room.json");
  const auto p = preprocess(scene, dir + "/t.fsd");
  ASSERT_EQ(p.exitCode, 0) << p.output;
  const auto r = firstshot::test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-1 " + kRender + " " + scene + " --firstshot " +
                                      dir + "/t.fsd --width 128 --height 128 --time 17 --seed 2 --threads 2 " +
                                      "--checkpoint 1000 -o " + dir + "/a.exr");
  ASSERT_EQ(r.exitCode, 130) << r.output;
  EXPECT_EQ(choice(r.output), "irradiance-cache") << r.output;
}

TEST(IntegratorAuto, VeachBidirWithItsTableGoesToLightTracing) {
  FIRSTSHOT_STATISTICS_ONLY("IntegratorAuto.ATableOfLuminairesAloneIsNotTriedTwice");
  // veach-bidir as it ships (../shared/scenes, skipped where absent), with its table at the defaults (a luminaire
  // about the wall lamp), 128 x 128 with the 12.4 s that 20 s leave after its preprocessing. Light tracing is the
  // best method there. With its wall lamp split where that pays, the table makes it better: at 20 s each, outside the
  // glass egg, 0.0457 with the table (--shoot-firstshot off), 0.0470 (patches), 0.0495 without; BDPT with the table
  // 0.0577 (docs/measurements.md, "Luminaires in BDPT; split where it pays"). While every luminaire was split the
  // table made it worse (0.0621 and 0.0691 against 0.0574 at 12 s), and the pilot had to have plain light tracing
  // among its candidates. Stopped after the render's first pass; seeds 1 to 4.
  const std::string scene = firstshot::test::source("../shared/scenes/veach-bidir/scene.xml");
  if (!std::filesystem::exists(scene)) GTEST_SKIP() << scene << " is absent (the public scenes live in ../shared/scenes)";
  const std::string dir = firstshot::test::tempDir();
  const auto p = preprocess(scene, dir + "/t.fsd");
  ASSERT_EQ(p.exitCode, 0) << p.output;
  for (const char* seed : {"1", "2", "3", "4"}) {
    const auto r = firstshot::test::run("FIRSTSHOT_TEST_INTERRUPT=render-pass-1 " + kRender + " " + scene +
                                        " --firstshot " + dir + "/t.fsd --width 128 --height 128 --time 12.4 --seed " +
                                        seed + " --threads 2 --checkpoint 1000 -o " + dir + "/a.exr");
    ASSERT_EQ(r.exitCode, 130) << r.output;
    EXPECT_THAT(choice(r.output), StartsWith("light")) << r.output;
  }
}

TEST(IntegratorAuto, PatchNeeIsChargedTheTimeItsSamplingTakes) {
  // Sampling the lit patches makes each of the path tracer's rays about 2.5× as costly in time (docs/integrators.md):
  // counted at one ray each, the pilot took `--patch-nee every` on the Ward sphere with its table (efficiency 1
  // against 0.858), where at 20 s `--patch-nee off` is 2.6× as efficient; counted at 2.5, `off` is ahead of it.
  // The table itself does not pay there: the path tracer without it is chosen (1.11× `--patch-nee off` at 20 s), the
  // render is the scene's as without --firstshot, and a resumed render takes that choice from its checkpoint.
  const std::string dir = firstshot::test::tempDir(), scene = dir + "/ward.json";
  ASSERT_TRUE(copyAt305Spp("scenes/ward-sphere.json", scene));
  const auto p = preprocess(scene, dir + "/t.fsd");
  ASSERT_EQ(p.exitCode, 0) << p.output;
  const std::string base = kRender + " " + scene + " --firstshot " + dir + "/t.fsd --width 128 --height 128";
  const auto r = firstshot::test::run(base + " --time 0.01 -o " + dir + "/a.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_GT(efficiency(r.output, "path --patch-nee off"), efficiency(r.output, "path --patch-nee every")) << r.output;
  EXPECT_EQ(choice(r.output), "path, no table") << r.output;
  EXPECT_THAT(r.output, HasSubstr("the table given is not read")) << r.output;
  EXPECT_THAT(r.output, HasSubstr("(0 replaced by first-shot)")) << r.output;
  // Stopped after two passes with a checkpoint, resumed: the checkpoint's choice, without the table again.
  std::string resumed;
  ASSERT_NO_FATAL_FAILURE(expectTheCheckpointKeepsTheChoice(base, dir + "/b.exr", "path, no table", resumed));
  EXPECT_THAT(resumed, HasSubstr("(0 replaced by first-shot)")) << resumed;
  // The picture is the path tracer's without --firstshot, byte for byte (64 x 64 at 305 spp: the same choice).
  const std::string small = kRender + " " + scene + " --width 64 --height 64 --spp 305 --seed 3";
  const auto unread = firstshot::test::run(small + " --firstshot " + dir + "/t.fsd -o " + dir + "/c.exr");
  ASSERT_EQ(unread.exitCode, 0) << unread.output;
  ASSERT_EQ(choice(unread.output), "path, no table") << unread.output;
  const auto plain = firstshot::test::run(small + " --integrator path -o " + dir + "/d.exr");
  ASSERT_EQ(plain.exitCode, 0) << plain.output;
  const std::string picture = firstshot::test::readFile(dir + "/c.exr");
  ASSERT_FALSE(picture.empty());
  EXPECT_EQ(picture, firstshot::test::readFile(dir + "/d.exr"));
}

TEST(IntegratorAuto, TheCornellBoxGoesToTheCache) {
  // The pilot's two images sample the same positions in their pixels (RenderOptions::jitterSeed): their difference
  // is the light's noise, not the edges' aliasing, which the render's stratified samples nearly remove. Without that
  // the Cornell box at 128 x 128, 305 spp (what --time 20 sizes) went to light tracing, where the path tracer is
  // 2.3x as efficient at 20 s (docs/measurements.md, "The pilot's two images at the same positions"), and it still
  // does. It goes to the cache since its fill is grown as pixels^0.8 (before, in proportion to the pixels, to the
  // path tracer): at 305 spp the cache is 7.9x the path tracer's efficiency outside the lamp (noise 0.0128 in 6.0 s
  // against 0.0451 in 3.8 s; 1.2x over the whole picture, the lamp's edges included), 2.8x at 20 s.
  const std::string dir = firstshot::test::tempDir(), scene = dir + "/cornell.json";
  ASSERT_TRUE(copyAt305Spp("scenes/cornell.json", scene));
  const auto r = firstshot::test::run(kRender + " " + scene + " --width 128 --height 128 --time 0.01 -o " + dir + "/a.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(choice(r.output), "irradiance-cache") << r.output;
  // The cache's records' error is measured with the positions shared too (a third image: the second fill's records
  // under the first image's passes); from the films' per-pixel variances, which hold the samples' spread over their
  // pixels, it came out 0 here.
  const auto error = r.output.find("its records' error ");
  ASSERT_NE(error, std::string::npos) << r.output;
  EXPECT_GT(std::atof(r.output.c_str() + error + 19), 0.0) << r.output;
  // Pixels where a sample one fill's records miss took a path are left out of it (that path is pass noise): some
  // samples of the 48 x 48 picture fall outside the 12 x 12 fill's records, most do not.
  const std::string missed = "; the ";
  const auto share = r.output.find(missed, error);
  ASSERT_NE(share, std::string::npos) << r.output;
  EXPECT_THAT(r.output.substr(share), HasSubstr("% of the pixels where a sample they miss took a path left out"));
  const double leftOut = std::atof(r.output.c_str() + share + missed.size());
  EXPECT_GT(leftOut, 0.0) << r.output;
  EXPECT_LT(leftOut, 50.0) << r.output;
}

// The cache's passes converge faster than 1/sqrt(passes) with the render's stratified samples (a smooth lookup and the
// direct light), and the pilot measures how over the fill's records. On the emissive-texture wall (128 x 128 at
// 305 spp, what --time 20 sizes; the rate does not depend on the budget) the rate (passes^-rate) over six seeds averaged 0.83
// (0.57-1.00); with independent samples in its images, 0.58 (0.50-0.81, about 0.13 a seed): the mean stands above
// that by 3 sigma.
TEST(IntegratorAuto, TheCachesPassesGainFromTheRendersStratifiedSamples) {
  const std::string dir = firstshot::test::tempDir();
  double sum = 0.0;
  const int seeds = 6;
  for (int seed = 1; seed <= seeds; ++seed) {
    const auto r = firstshot::test::run(kRender + " " + firstshot::test::source("scenes/emissive-texture.json") +
                                        " --width 128 --height 128 --spp 305 --threads 2 --seed " +
                                        std::to_string(seed) + " -o " + dir + "/a.exr");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string key = "its passes' noise falling as passes^-";
    const auto at = r.output.find(key);
    ASSERT_NE(at, std::string::npos) << r.output;
    sum += std::atof(r.output.c_str() + at + key.size());
  }
  EXPECT_GT(sum / seeds, 0.58 + 3.0 * 0.13 / std::sqrt(double(seeds)));
}

TEST(IntegratorAuto, ASunAndSkyGoToNeeToEveryLight) {
  // Where a scene has more than one light the path tracer with --light-sampler all is a candidate too: in the sky
  // courtyard (sun and sky) it is 6.6x the light tree's efficiency at 20 s, and the pilot takes it (3.5x there at
  // 128 x 128, 305 spp). A resumed render takes it from its checkpoint.
  const std::string dir = firstshot::test::tempDir(), scene = dir + "/court.json";
  ASSERT_TRUE(copyAt305Spp("scenes/sky-courtyard.json", scene));
  const std::string base = kRender + " " + scene + " --width 128 --height 128";
  std::string resumed;
  ASSERT_NO_FATAL_FAILURE(expectTheCheckpointKeepsTheChoice(base, dir + "/a.exr", "path --light-sampler all", resumed));
  // Given --light-sampler, the option is the user's: no such candidate.
  const auto given = firstshot::test::run(base + " --light-sampler tree --time 0.01 -o " + dir + "/b.exr");
  ASSERT_EQ(given.exitCode, 0) << given.output;
  EXPECT_EQ(pilotTable(given.output).find("--light-sampler all"), std::string::npos) << given.output;
}
