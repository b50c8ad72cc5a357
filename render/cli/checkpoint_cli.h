#pragma once
/// @file checkpoint_cli.h
/// firstshot-render's --checkpoint, --checkpoint-file and --resume (header-only, included by
/// render/cli/render_command.cpp, which links CLI11): the options, the key of what decides the image, and the
/// render loop that saves and restores checkpoints (render/loop/checkpoint.h; docs/robustness.md).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "common/util/interrupt.h"
#include "render/integrators/integrator.h"
#include "render/loop/checkpoint.h"
#include "render/loop/renderer.h"

namespace firstshot {

/// The checkpoint key's entry of a render that --integrator auto chose to make without the --firstshot table given.
inline constexpr const char* kTableUnusedKey = "firstshot-table";
/// The checkpoint key's entry of the hemisphere rays per record the render's cache took (IntegratorCli::recordSamples:
/// --integrator auto may have taken more than the option's value).
inline constexpr const char* kRecordSamplesKey = "--ic-samples";

struct CheckpointCli {
  double every = 0;  ///< seconds between checkpoints; 0 = none
  std::string file;  ///< the checkpoint file (default: the first output + ".checkpoint")
  bool resume = false;
  CheckpointKey key;
  int passes = 0;    ///< sample indices every pixel held when the render started (resume) or holds now

  void add(CLI::App& app) {
    app.add_option("--checkpoint", every, "save the render's state every SECONDS (at pass boundaries) and on "
                                          "SIGINT/SIGTERM, for --resume (docs/robustness.md)")
        ->check(CLI::Range(1e-3, 1e9));
    app.add_option("--checkpoint-file", file, "the checkpoint file (default: the first output + \".checkpoint\")");
    app.add_flag("--resume", resume, "continue the render saved in the checkpoint file; the image then equals an "
                                     "uninterrupted render's, bit for bit");
  }
  bool active() const { return every > 0 || resume; }
  /// The checkpoint file: --checkpoint-file, else the first of @p outputs + ".checkpoint".
  std::string path(const std::vector<std::string>& outputs) const {
    return !file.empty() ? file : outputs.empty() ? std::string() : outputs.front() + ".checkpoint";
  }

  /// Checks the options against the rest of the command line and picks the file.
  /// @throws InputError for a combination that cannot resume exactly.
  void configure(const CLI::App& app, const std::vector<std::string>& outputs, const Integrator& integrator) {
    if (!file.empty() && !active()) throw InputError("", "--checkpoint-file", "only with --checkpoint or --resume");
    if (!active()) return;
    if (app.count("--preview")) throw InputError("", "--checkpoint", "not available with --preview");
    if (const std::string why = integrator.notResumable(); !why.empty())
      throw InputError("", every > 0 ? "--checkpoint" : "--resume", why);
    file = path(outputs);
    const auto dir = std::filesystem::path(file).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) throw InputError(file, "--checkpoint-file", "the folder does not exist");
  }

  /// The key: content hashes of the inputs, the resolved values and every option that can change
  /// the image (all but those listed below, which only change outputs, speed or the sample count).
  void makeKey(const CLI::App& app, const std::string& scenePath, const SceneDesc& scene, const std::string& fsdPath,
               const std::string& integratorName, uint64_t seed, int maxDepth, const std::string& inputFile) {
    key = {{"scene-file", fileContentHash(scenePath)},
           {"scene", fmt::format("{:016x}", hashScene(scene))},
           {"firstshot", fileContentHash(fsdPath)},
           {"integrator", integratorName},
           {"width", std::to_string(scene.camera.width)},
           {"height", std::to_string(scene.camera.height)},
           {"seed", std::to_string(seed)},
           {"max-depth", std::to_string(maxDepth)},
           {"cache-file", fileContentHash(inputFile)}};
    static const char* const kIgnored[] = {"scene", "--firstshot", "--integrator", "--spp", "--time", "--iterations",
                                           "--output", "--threads", "--seed", "--max-depth", "--width", "--height",
                                           "--exposure", "--aov", "--quiet", "--help", "--preview", "--frames",
                                           "--screenshot", "--window-grab", "--cache-file", "--show-records",
                                           "--checkpoint", "--checkpoint-file", "--resume"};
    for (const CLI::Option* o : app.get_options()) {
      if (std::any_of(std::begin(kIgnored), std::end(kIgnored), [&](const char* n) { return o->check_name(n); })) continue;
      std::string value;
      if (o->count() == 0) value = o->get_default_str();
      else
        for (const std::string& r : o->results()) value += (value.empty() ? "" : ",") + r;
      key.emplace_back(o->get_name(), value);
    }
  }

  /// render() with checkpoints: restores the film with --resume, saves it every `every` seconds
  /// between passes, and stops at SIGINT/SIGTERM (see saveAfterInterrupt()). @p ro.spp is the
  /// total; the returned RenderStats::spp counts the passes of the restored film too.
  RenderStats render(const Integrator& integrator, const Camera& camera, Film& film, RenderOptions ro) {
    ro.cancel = &interruptFlag();
    if (!active()) return firstshot::render(integrator, camera, film, ro);
    if (resume) {
      passes = readCheckpoint(file, key, film);
      const uint32_t most = *std::max_element(film.sums().count.begin(), film.sums().count.end());
      if (ro.timeLimit <= 0 && int(most) > ro.spp)
        throw InputError(file, "--spp", fmt::format("the checkpoint holds {} passes, more than --spp {}", most, ro.spp));
      ro.firstSample = passes;
      ro.spp -= passes;
      ro.skipTaken = true;
      if (ro.timeLimit <= 0 && ro.spp == 0) {  // nothing left to render
        RenderStats st;
        st.spp = passes;
        return st;
      }
    }
    auto last = std::chrono::steady_clock::now();
    ro.afterPass = [&](int done) {
      testInterruptPoint("render-pass-" + std::to_string(done));
      const auto now = std::chrono::steady_clock::now();
      if (every > 0 && std::chrono::duration<double>(now - last).count() >= every) {
        writeCheckpoint(file, key, film);
        last = now;
      }
    };
    RenderStats st = firstshot::render(integrator, camera, film, ro);
    st.spp += ro.firstSample;
    return st;
  }

  /// After an interruption: saves the film (when checkpointing or resuming) and returns the
  /// exception to throw, which says where the checkpoint is.
  Interrupted saveAfterInterrupt(const Interrupted& e, const Film& film) const {
    if (!active()) return e;
    writeCheckpoint(file, key, film);
    const uint32_t done = *std::min_element(film.sums().count.begin(), film.sums().count.end());
    return Interrupted(e.signal(), fmt::format("no output written; checkpoint of {} passes saved to {} (continue with "
                                               "the same options and --resume)", done, file));
  }

  /// After a complete render and its outputs: the checkpoint is no longer needed and is deleted.
  void finished() const {
    if (!active()) return;
    std::error_code ec;
    std::filesystem::remove(file, ec);
  }
};

}  // namespace firstshot
