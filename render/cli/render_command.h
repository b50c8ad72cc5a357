#pragma once
/// @file render_command.h
/// firstshot-render's command line in named steps (render/cli/main.cpp runs it): declare the options,
/// parse and check them, load the scene, make the integrator, then one of three modes: sensors
/// (render/cli/sensors_cli.h), the preview window (render/preview/) or an image (with checkpoints,
/// render/cli/checkpoint_cli.h). The integrators' options: render/cli/integrator_options.h.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/sampling/rng.h"
#include "common/scene/scene_desc.h"
#include "common/util/comm.h"
#include "render/cli/checkpoint_cli.h"
#include "render/cli/falsecolor_cli.h"
#include "render/cli/integrator_options.h"
#include "render/cli/sensors_cli.h"
#include "render/integrators/integrator.h"
#include "render/scene/render_scene.h"

namespace firstshot {

class RenderCommand {
 public:
  /// @p comm: the ranks of the run (docs/mpi.md).
  explicit RenderCommand(Comm& comm);
  /// Runs the tool on @p argv; returns its exit code. @throws InputError for bad input.
  int run(int argc, char** argv);

 private:
  void declareOptions();
  /// The checks that need no scene.
  void checkOptions();
  /// Loads the scene, resizes its camera and reads the sensor sets that need it.
  void loadScene();
  /// --daylight-factor: makes scene_ the CIE overcast sky alone (render/sensors/daylight_factor.h), says so on stderr.
  void switchToDaylightFactorScene();
  /// --integrator auto: chooses the integrator and its table options, by a pilot where the render is an image
  /// (render/loop/integrator_pilot.h), and says so on stderr (render/cli/render_command_auto.cpp).
  void resolveIntegrator();
  void leaveTableUnread();  // --integrator auto: the render is the scene's without the --firstshot table
  /// An integrator named whose records gather hemisphere rays (the irradiance cache: IntegratorCli::recordSamples),
  /// with --time and no --ic-samples: their rays sized to the render's budget by a pilot of it alone
  /// (bestRecordSamples), or as the checkpoint resumed holds them.
  void sizeRecords();
  /// The chosen cache's records at @p f's rays per record (@p pilotRays × f.recordSamples), or where this machine's
  /// fill would be stopped by --time (past kFillTimeShare of the time left), fewer (recordSamplesForTime); says so on
  /// stderr. Only where --time stops a fill (one rank, no checkpoint).
  void fitRecordsToTime(const PilotFigure& f, int pilotRays);
  /// --integrator auto's report on stderr: the pilot's figures of @p candidates, which rank, the one chosen (@p best),
  /// the cache's fill as projected (@p recordSamples: each candidate's hemisphere rays per record in the pilot).
  void printPilot(const std::vector<PilotCandidate>& candidates, const std::vector<PilotFigure>& figures,
                  const PilotPlan& plan, int spp, const std::vector<uint8_t>& ranked, const std::vector<size_t>& robust,
                  size_t best, const std::vector<int>& recordSamples) const;
  /// The pilot of @p candidates candidates for this render (its samples per pixel into @p spp).
  PilotPlan pilotPlan(size_t candidates, int& spp) const;
  /// Makes a pilot candidate's integrator with @p base's options and the candidate's own.
  PilotFactory pilotFactory(const IntegratorOptions& base);
  /// The longest path in bounces: --max-depth or the scene's, one less for sensors.
  int maxDepth() const;
  /// Checks the chosen integrator's options against the scene and makes it.
  void makeIntegrator();
  /// The scene the integrator traces: the table's patches, or the scene's faces (cut into patches
  /// where the integrator needs them).
  void buildRenderScene();
  /// Rejects a bad image name before the render, not after.
  void checkImageOutputs() const;
  int renderSensors();
  int runPreview();
  int renderImage();
  /// --seed, or the scene's.
  uint64_t seed() const;
  /// --sampler: how every integrator, the sensors and the preview draw their numbers.
  SamplerMode samplerMode() const;
  /// The render samples adaptively (--adaptive; never with --checkpoint, whose files hold whole passes).
  bool adaptiveRender() const;

  Comm& comm_;
  CLI::App app_;
  std::string scenePath_, fsdPath_, samplerName_ = "sobol", screenshot_, windowGrab_;
  std::string adaptive_ = "auto";  ///< --adaptive
  std::vector<std::string> outputs_;
  int spp_ = 0, threads_ = 0, maxDepth_ = -1, width_ = 0, height_ = 0, frames_ = -1;
  double timeLimit_ = 0, patchSize_ = 0;
  double pilotSeconds_ = 0;  // --integrator auto's pilot, wall time (taken from --time's budget)
  float exposure_ = 0;
  uint64_t seed_ = 0;
  bool quiet_ = false, aov_ = false, preview_ = false;
  bool tableUnused_ = false;  // --integrator auto chose to render without the --firstshot table
  IntegratorOptionsCli integrators_;  // --integrator, --primary, ..., and each integrator's own
  CheckpointCli checkpoint_;          // --checkpoint, --checkpoint-file, --resume
  SensorsCli sensors_;                // --sensors, --grid, --samples, --efficacy
  FalseColorCli photometric_;         // --units, --falsecolor, --falsecolor-*

  std::vector<SensorSet> sensorSets_;
  SceneDesc scene_;
  IntegratorOptions integratorOptions_;
  std::unique_ptr<Integrator> integrator_;
  std::unique_ptr<RenderScene> renderScene_;
};

}  // namespace firstshot
