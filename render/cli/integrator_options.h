#pragma once
/// @file integrator_options.h
/// firstshot-render's --integrator, the options that set IntegratorOptions (shared by several
/// integrators, declared here once) and each integrator's own options (declared by its command line,
/// render/integrators/integrator_cli.h, one per line of integratorTable()). An option given on the command line
/// that the chosen integrator does not read is an error that names it and the integrators that read
/// it (header-only, included by render/cli/render_command.cpp, which links CLI11).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "common/util/error.h"
#include "render/integrators/integrator.h"
#include "render/integrators/integrator_cli.h"
#include "render/loop/integrator_pilot.h"

namespace firstshot {

struct IntegratorOptionsCli {
  static constexpr const char* kAuto = "auto";  ///< --integrator auto
  std::string name = "auto", primary = "exact", lightSampler = "tree", patchNee = "off", lightVisibility = "on",
              shootFirstShot = "patches", tableVisibility = "on", luminaires = "on", emitterChoice = "camera";
  /// One command line per line of integratorTable(), in its order.
  std::vector<std::unique_ptr<IntegratorCli>> clis;

  IntegratorOptionsCli() {
    for (const IntegratorEntry& e : integratorTable()) clis.push_back(e.cli());
  }

  /// Declares --integrator and the shared options.
  void addShared(CLI::App& app) {
    using namespace integrator_option;
    std::string list;
    for (const IntegratorEntry& e : integratorTable())
      list += fmt::format("{}{}{}", list.empty() ? "" : " | ", e.name,
                          *e.description ? fmt::format(" ({})", e.description) : std::string());
    app.add_option("--integrator", name, "integrator: auto (a pilot of a few percent of the samples measures "
                                         "path, irradiance-cache, light and bdpt on the scene, each with and without "
                                         "the table's options, the path tracer also without the table and with "
                                         "--light-sampler all, and renders with the most efficient; "
                                         "docs/integrators.md) | " + list)->capture_default_str();
    app.add_option(kPrimary, primary, "with --firstshot, camera-visible surfaces: exact (shadow rays to small lights) "
                                      "or patch (first-shot there too)")
        ->check(CLI::IsMember({"exact", "patch"}))->capture_default_str();
    app.add_option(kLightSampler, lightSampler, "next-event estimation: tree (one light per vertex, chosen by a light "
                                                "tree) or all (one sample of every light per vertex)")
        ->check(CLI::IsMember({"tree", "all"}))->capture_default_str();
    app.add_option(kPatchNee, patchNee, "with --firstshot: sample the lit first-shot patches as light sources at "
                                        "the first surface of a path (first), at every surface (every) or not (off)")
        ->check(CLI::IsMember({"first", "every", "off", "on"}))->capture_default_str();
    app.add_option(kLightVisibility, lightVisibility, "light tree: weight its choices by the visibility of the "
                                                      "lights from each region, estimated with a few rays per region")
        ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
    app.add_option(kTableVisibility, tableVisibility, "with --firstshot and --primary exact, camera-visible "
                                                      "surfaces: no shadow ray to a small point or spot light "
                                                      "the table finds visible from the whole patch or from none "
                                                      "of it (on), or shadow rays to all (off)")
        ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
    app.add_option(kShootFirstShot, shootFirstShot, "light and bdpt with --firstshot: the small lights' particles "
                                                    "start from the patches the table lights (patches) or the "
                                                    "table is ignored (off; docs/light-tracing.md, docs/bdpt.md)")
        ->check(CLI::IsMember({"patches", "off"}))->capture_default_str();
    app.add_option(kLuminaires, luminaires, "path, irradiance-cache, light and bdpt with --firstshot: sample (path, "
                                            "cache, bdpt) or shoot from (light, bdpt) the table's luminaires' exit "
                                            "patches and see through their boxes (on), or take their lights as "
                                            "ordinary lights (off; docs/luminaires.md)")
        ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
    app.add_option(kEmitterChoice, emitterChoice, "light and bdpt: the particles' lights chosen by what the camera "
                                                  "sees of each one's light (camera) or by their power (power; "
                                                  "docs/light-tracing.md)")
        ->check(CLI::IsMember({"camera", "power"}))->capture_default_str();
  }

  /// Declares every integrator's own options.
  void addOwn(CLI::App& app) {
    for (const auto& cli : clis) cli->add(app);
  }

  /// The command line of the integrator named @p integrator. @throws InputError for an unknown name.
  IntegratorCli& cli(const std::string& integrator) const {
    return *clis[size_t(&integratorEntry(integrator) - integratorTable().data())];
  }
  /// The chosen integrator's command line. @throws InputError for an unknown --integrator.
  IntegratorCli& chosen() const { return cli(name); }
  /// --integrator auto: the integrator is not chosen yet (resolveAuto).
  bool isAuto() const { return name == kAuto; }

  /// --integrator auto: the settings the pilot may choose from (render/loop/integrator_pilot.h). The integrators
  /// that read every integrator option given on @p app (an option only some read narrows the choice to them),
  /// and, with a table that replaces lights (@p table), each with --patch-nee off and every (path, irradiance-cache) or
  /// --shoot-firstshot patches and off (light, bdpt) unless that option was given. With a table given (@p tableGiven)
  /// and none of its options, the path tracer also without the table; where the scene has more than one light
  /// (@p manyLights) and --light-sampler is not given, the path tracer with --light-sampler all too (without the
  /// table given, if one is: last). The bundle only when the options given leave nothing else; with a sky or
  /// environment map (@p infinite) only path and irradiance-cache.
  /// @throws InputError when no integrator reads every option given.
  std::vector<PilotCandidate> autoCandidates(const CLI::App& app, bool table, bool tableGiven, bool luminaires,
                                             bool manyLights, bool infinite, const std::string& sceneFile) const {
    using namespace integrator_option;
    std::vector<std::string> given, readers, pilotReaders;
    for (const auto& cli : clis)
      for (const std::string& option : cli->options())
        if (app.count(option) && std::find(given.begin(), given.end(), option) == given.end()) given.push_back(option);
    for (size_t i = 0; i < clis.size(); ++i) {
      const std::vector<std::string> theirs = clis[i]->options();
      bool all = true;
      for (const std::string& option : given) all = all && std::find(theirs.begin(), theirs.end(), option) != theirs.end();
      const std::string n = integratorTable()[i].name;
      if (!all) continue;
      readers.push_back(n);
      if (n != "bundle" && (!infinite || n == "path" || n == "irradiance-cache")) pilotReaders.push_back(n);
    }
    if (readers.empty()) {
      std::string list;
      for (const std::string& option : given) list += (list.empty() ? "" : " ") + option;
      throw InputError("", "--integrator", "auto: no integrator reads all of " + list + " (choose one with --integrator)");
    }
    if (pilotReaders.empty()) {
      if (infinite && readers.front() != "bundle")
        throw InputError(sceneFile, "sky", "the options given are read only by integrators that do not support a "
                                           "sky/environment yet (use --integrator path or irradiance-cache)");
      pilotReaders.push_back(readers.front());
    }
    const IntegratorOptions fixed = options(0);  // --patch-nee, --shoot-firstshot as given or by default
    const bool unread = tableGiven && app.count(kPatchNee) == 0 && app.count(kShootFirstShot) == 0;
    std::vector<PilotCandidate> out;
    for (const std::string& n : pilotReaders) {
      PilotCandidate c;
      c.integrator = n;
      c.patchNee = fixed.patchNee;
      c.shootFromPatches = fixed.shootFromPatches;
      const std::vector<std::string> theirs = cli(n).options();
      auto reads = [&](const char* o) { return std::find(theirs.begin(), theirs.end(), o) != theirs.end(); };
      // A shooting integrator's --patch-nee serves only its path-traced pixels: it varies --shoot-firstshot.
      const bool nee = table && app.count(kPatchNee) == 0 && reads(kPatchNee) && !reads(kShootFirstShot);
      const bool shoot = table && app.count(kShootFirstShot) == 0 && reads(kShootFirstShot);
      if (nee) {
        c.variesPatchNee = true;
        for (const PatchNee p : {PatchNee::Off, PatchNee::Every}) {
          c.patchNee = p;
          out.push_back(c);
        }
      } else if (shoot) {
        c.variesShoot = true;
        for (const bool s : {true, false}) {
          c.shootFromPatches = s;
          out.push_back(c);
        }
      } else {
        out.push_back(c);
      }
    }
    // A table that does not pay (its lookups cost more than its smoother light saves) is left unread: the path
    // tracer as without --firstshot, what the defaults give without a table, and where the table has luminaires
    // light tracing too. Not where the user asked for one of the table's options. (Light tracing with
    // --shoot-firstshot off is the plain light tracer but for the luminaires, whose exit light it shoots: on
    // veach-bidir, outside the egg, 0.85× the plain light tracer's efficiency at equal time, 0.69× with the patches
    // shot; in the fixture room 0.75×. Without luminaires it is the same picture, and plain light tracing as one more
    // candidate won only by the table readers' weight, over the cache + table 3.6× as efficient in the textured
    // room. BDPT without the table won no pilot without a table. The cache without the table, tried, made the pilot
    // leave tables that pay: it measures the cache's records' error coarsely.)
    auto reads = [&](const char* n) { return std::find(pilotReaders.begin(), pilotReaders.end(), n) != pilotReaders.end(); };
    const bool path = reads("path");
    PilotCandidate plain;
    plain.integrator = "path";
    plain.patchNee = fixed.patchNee;
    plain.shootFromPatches = fixed.shootFromPatches;
    plain.table = !tableGiven;
    if (unread && path) out.push_back(plain);
    if (unread && luminaires && reads("light")) {
      PilotCandidate light = plain;
      light.integrator = "light";
      out.push_back(light);
    }
    // NEE to every light, the other way a user samples many lights without a table: on Veach MIS 3.8× the light
    // tree's efficiency at 20 s, in the classroom (sun and sky) 1.5×.
    if (manyLights && app.count(kLightSampler) == 0 && (unread || !tableGiven) && path) {
      plain.everyLight = true;
      out.push_back(plain);
    }
    return out;
  }

  /// Makes @p c the choice: --integrator, --patch-nee and --shoot-firstshot as the candidate has them.
  void choose(const PilotCandidate& c) {
    name = c.integrator;
    patchNee = c.patchNee == PatchNee::Off ? "off" : c.patchNee == PatchNee::First ? "first" : "every";
    shootFirstShot = c.shootFromPatches ? "patches" : "off";
    if (c.everyLight) lightSampler = "all";
  }

  /// @throws InputError for an option given on @p app that the chosen integrator does not read, e.g.
  /// "--shoot-firstshot: not used by --integrator path (used by: light, bdpt)".
  void requireUsed(const CLI::App& app) const {
    const std::vector<std::string> mine = chosen().options();
    std::vector<std::string> checked;
    for (const auto& cli : clis)
      for (const std::string& option : cli->options()) {
        if (std::find(checked.begin(), checked.end(), option) != checked.end()) continue;
        checked.push_back(option);
        if (app.count(option) == 0 || std::find(mine.begin(), mine.end(), option) != mine.end()) continue;
        std::string users;
        for (size_t i = 0; i < clis.size(); ++i) {
          const std::vector<std::string> theirs = clis[i]->options();
          if (std::find(theirs.begin(), theirs.end(), option) != theirs.end())
            users += fmt::format("{}{}", users.empty() ? "" : ", ", integratorTable()[i].name);
        }
        throw InputError("", option, fmt::format("not used by --integrator {} (used by: {})", name, users));
      }
  }

  /// The shared options' values (@p maxDepth: the bounces, resolved).
  IntegratorOptions options(int maxDepth) const {
    IntegratorOptions io;
    io.maxDepth = maxDepth;
    io.primary = primary == "patch" ? PrimaryMode::Patch : PrimaryMode::Exact;
    io.lightSampler = lightSampler == "all" ? LightStrategy::All : LightStrategy::Tree;
    io.patchNee = patchNee == "off" ? PatchNee::Off : patchNee == "first" ? PatchNee::First : PatchNee::Every;
    io.lightVisibility = lightVisibility == "on";
    io.tableVisibility = tableVisibility == "on";
    io.shootFromPatches = shootFirstShot == "patches";
    io.luminaires = luminaires == "on";
    io.cameraEmitterChoice = emitterChoice == "camera";
    return io;
  }
};

}  // namespace firstshot
