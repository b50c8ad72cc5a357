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

#include "common/error.h"
#include "render/integrators/integrator.h"
#include "render/integrators/integrator_cli.h"

namespace fs {

struct IntegratorOptionsCli {
  std::string name = "path", primary = "exact", lightSampler = "tree", patchNee = "off", lightVisibility = "on",
              shootFirstShot = "patches", tableVisibility = "on";
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
    app.add_option("--integrator", name, "integrator: " + list)->capture_default_str();
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
    return io;
  }
};

}  // namespace fs
