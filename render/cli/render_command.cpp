// firstshot-render's command line: the steps of RenderCommand::run().
#include "render/cli/render_command.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "common/formats/load_scene.h"
#include "common/patches/patch_size.h"
#include "common/scene/camera_fov.h"
#include "common/table/firstshot.h"
#include "common/util/cli.h"
#include "common/util/interrupt.h"
#include "render/loop/renderer.h"
#include "render/output/film.h"
#include "render/preview/preview_app.h"
#include "render/scene/camera.h"

namespace firstshot {

RenderCommand::RenderCommand(Comm& comm)
    : comm_(comm),
      app_("firstshot-render: renders a scene with the Embree path tracer, optionally replacing small lights by "
           "their first-shot factors") {}

int RenderCommand::run(int argc, char** argv) {
  declareOptions();
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app_.exit(e) == 0 ? 0 : kExitBadInput;
  }
  // SIGINT/SIGTERM: stop, write no image (a checkpoint with --checkpoint), exit 130/143 (docs/robustness.md).
  if (!preview_) installInterruptHandlers();
  checkOptions();
  loadScene();
  resolveIntegrator();
  makeIntegrator();
  if (!renderScene_) buildRenderScene();  // the pilot may have built it
  if (sensors_.active()) return renderSensors();
  if (preview_) return runPreview();
  return renderImage();
}

void RenderCommand::declareOptions() {
  CLI::App& app = app_;
  app.add_option("scene", scenePath_, "scene file (.json, .obj, .gltf, .glb, .ply)")->required();
  app.add_option("--firstshot", fsdPath_, "first-shot table from firstshot-preprocess (.fsd)");
  integrators_.addShared(app);
  auto* sppOpt = app.add_option("--spp", spp_, "samples per pixel (default: the scene's settings.spp)")->check(CLI::Range(1, 1 << 30));
  app.add_option("--time", timeLimit_, "render passes of 1 spp until this many seconds have passed, the auto pilot "
                                       "and the integrator's preprocessing (the cache's fill, which stops at three "
                                       "quarters of what the pilot leaves, without --checkpoint) included (the image then "
                                       "depends on how many passes fit)")
      ->check(CLI::Range(1e-3, 1e9))->excludes(sppOpt);
  app.add_option("--adaptive", adaptive_, "samples where the pixels' noise is (on): after 16 passes, rounds that give "
                                          "each pixel one sample and as many again by the pixels' estimated error "
                                          "(--spp then their mean; light tracing: more path-traced estimates at "
                                          "mirrors and glass within each pass; not BDPT); off: passes of 1 spp; auto: "
                                          "on with --time, off with --spp (off with --checkpoint and the bundle)")
      ->check(CLI::IsMember({"auto", "on", "off"}))->capture_default_str();
  auto* outOpt = app.add_option("-o,--output", outputs_, "output image, .exr (linear float) or .png (sRGB); may be repeated "
                                                         "(required without --preview)");
  app.add_option("--threads", threads_, "worker threads (default: one per core); the image does not depend on it")
      ->check(CLI::Range(0, 4096));
  app.add_option("--seed", seed_, "random seed (default: the scene's settings.seed)");
  app.add_option("--sampler", samplerName_, "samples' numbers (every integrator, the sensors, the preview): "
                                            "sobol (per pixel Owen-scrambled "
                                            "Sobol' pairs, stratified over the samples; the lower error: "
                                            "docs/measurements.md) or independent (a hash per pixel, sample and "
                                            "dimension; for statistics that need independent samples)")
      ->check(CLI::IsMember({"independent", "sobol"}))->capture_default_str();
  app.add_option("--max-depth", maxDepth_, "longest path in bounces (default: the scene's settings.max_depth)")
      ->check(CLI::Range(0, 1 << 30));
  app.add_option("--exposure", exposure_, "PNG exposure in stops (scale by 2^exposure)");
  app.add_flag("--aov", aov_, "EXR: add albedo and normal layers for external denoisers");
  app.add_option("--width", width_, "image width (default: the scene's camera; the field of view on the scene's axis is "
                                    "kept: the vertical one, or a Mitsuba sensor's fov_axis)")->check(CLI::Range(1, 1 << 16));
  app.add_option("--height", height_, "image height (default: the scene's camera; as --width)")->check(CLI::Range(1, 1 << 16));
  app.add_option("--patch-size", patchSize_, "without --firstshot: longest patch edge in metres (default: every face as it is; --integrator bundle: "
                                             "the scene's patch_size, else automatic as the preprocessor's)")
      ->check(CLI::Range(1e-6, 1e6));
  app.add_flag("-q,--quiet", quiet_, "no progress bar or summary");
  auto* previewOpt = app.add_flag("--preview", preview_, "open the interactive preview window (needs a display; keys: H)")
                         ->excludes(outOpt);
  app.add_option("--frames", frames_, "with --preview: scripted run: refine for this many frames (1 spp each; the image "
                                      "then equals an offline render with --spp frames), save --screenshot, exit")
      ->check(CLI::Range(0, 1 << 30))->needs(previewOpt);
  app.add_option("--screenshot", screenshot_, "with --preview: screenshot file OUT.png (OUT.exr is written beside it); "
                                              "key P saves OUT-NNN.png")
      ->needs(previewOpt);
  app.add_option("--window-grab", windowGrab_, "with --preview --frames: save the window's pixels as shown (.png), for tests")
      ->needs(previewOpt);
  integrators_.addOwn(app);  // --light-paths, --accuracy, ..., --iterations, ... (render/integrators/*/cli.h)
  checkpoint_.add(app);
  sensors_.add(app);
  photometric_.add(app);
}

void RenderCommand::checkOptions() {
  if (!integrators_.isAuto()) integrators_.requireUsed(app_);  // auto: the options given narrow its choice
  sensors_.checkOptions(app_, outputs_);
  sensorSets_ = sensors_.sets();  // --grid-quad sets join once the scene is loaded
  photometric_.checkOptions(app_, sensors_.active(), sensorSets_, outputs_);
  if (!preview_ && outputs_.empty()) throw InputError("", "--output", "an output image is required (or use --preview)");
  if (comm_.size() > 1)  // docs/mpi.md: what is split over ranks
    for (const char* option : {"--preview", "--checkpoint", "--resume"})
      if (app_.count(option))
        throw InputError("", option, fmt::format("not available in an MPI run of {} ranks (run it with one)", comm_.size()));
  quiet_ = quiet_ || !comm_.root();  // rank 0 shows progress and prints the results
  if (preview_ && app_.count("--time")) throw InputError("", "--time", "not available with --preview (use --spp)");
  for (const std::string* png : {&screenshot_, &windowGrab_}) {
    if (png->empty()) continue;
    const std::string ext = std::filesystem::path(*png).extension().string();
    if (ext != ".png" && ext != ".PNG") throw InputError(*png, "", "the screenshot must be a .png file");
    const auto dir = std::filesystem::path(*png).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) throw InputError(*png, "", "the output folder does not exist");
  }
}

void RenderCommand::loadScene() {
  scene_ = firstshot::loadScene(scenePath_);
  if (sensors_.daylightFactor) switchToDaylightFactorScene();
  sensors_.addQuadGrids(scene_, sensorSets_);  // --grid-quad: on the scene's quads
  if (width_ > 0 || height_ > 0)  // the field of view on the scene's axis is kept (a Mitsuba fov_axis x: the horizontal)
    resizeCamera(scene_.camera, width_ > 0 ? width_ : scene_.camera.width, height_ > 0 ? height_ : scene_.camera.height);
  if (!preview_ && !sensors_.active()) Film::requireFits(scene_.camera.width, scene_.camera.height, scene_.file);  // before any other work
}

void RenderCommand::switchToDaylightFactorScene() {  // --daylight-factor: the CIE overcast sky alone
  const DaylightFactorSetup setup = daylightFactorScene(scene_);
  if (!fsdPath_.empty() && !setup.switchedOff.empty())
    throw InputError(fsdPath_, "--firstshot",
                     "--daylight-factor switches the scene's lights off, so a table of them does not apply (render "
                     "without --firstshot, or give a table of a scene without lights)");
  sensors_.outsideLux = setup.outsideLux;
  std::string off;
  for (const auto& name : setup.switchedOff) off += (off.empty() ? "" : ", ") + name;
  if (comm_.root())
    fmt::print(stderr, "firstshot-render: daylight factor under the CIE overcast sky alone (E_outside {:.6g} lx); "
                       "switched off: {}\n", setup.outsideLux, off.empty() ? "nothing (no sun, lights or emission)" : off);
}

uint64_t RenderCommand::seed() const { return app_.count("--seed") ? seed_ : scene_.settings.seed; }

bool RenderCommand::adaptiveRender() const {
  return (adaptive_ == "on" || (adaptive_ == "auto" && timeLimit_ > 0)) && !checkpoint_.active();
}

SamplerMode RenderCommand::samplerMode() const {
  return samplerName_ == "sobol" ? SamplerMode::Sobol : SamplerMode::Independent;
}

int RenderCommand::maxDepth() const {
  const int depth = maxDepth_ >= 0 ? maxDepth_ : scene_.settings.maxDepth;
  // A sensor is a camera-visible point (vertex 0): its cosine rays' first hits are bounce 1.
  return sensors_.active() ? std::max(0, depth - 1) : depth;
}

void RenderCommand::makeIntegrator() {
  integratorOptions_ = integrators_.options(maxDepth());
  integratorOptions_.comm = &comm_;
  IntegratorSetup setup{&app_, &scene_, seed(), threads_, spp_, samplerMode(), quiet_};
  IntegratorCli& cli = integrators_.chosen();
  cli.configure(setup);
  spp_ = setup.spp;
  integrator_ = cli.make(integratorOptions_);
  // Only the path walk and the irradiance cache meet the infinite light (NEE, escaped paths, background).
  if ((scene_.sky || scene_.environment) && integrators_.name != "path" && integrators_.name != "irradiance-cache")
    throw InputError(scene_.file, scene_.sky ? "sky" : "environment",
                     "the " + integrators_.name +
                         " integrator does not support a sky/environment yet (use --integrator path or irradiance-cache)");
  checkpoint_.configure(app_, outputs_, *integrator_);
  if (sensors_.active()) requireSensorIntegrator(*integrator_);
  checkImageOutputs();
}

void RenderCommand::buildRenderScene() {
  if (!fsdPath_.empty() && !tableUnused_) {
    FirstShotTable table = readFirstShot(fsdPath_, hashScene(scene_));
    // Sensors take a luminaire as one only where most of its light leaves through glass or off mirrors (its specular
    // light, a point source sampled exactly up to its bins): a lamp in a glass bulb is then found by every sensor's
    // NEE. Elsewhere its lights are lights (unbiased; the exit table's patch × bin blur is a few per cent at a
    // bowl's hot spot, where a lighting designer puts a sensor first: docs/luminaires.md).
    if (sensors_.active())
      std::erase_if(table.luminaires,
                    [](const Luminaire& l) { return !(luminance(l.specularPower) > luminance(l.exitPower)); });
    renderScene_ = std::make_unique<RenderScene>(scene_, std::move(table), fsdPath_);
  } else {
    renderScene_ = std::make_unique<RenderScene>(
        scene_, patchSize_ > 0 || integrators_.isAuto() || !integrators_.chosen().needsPatches() ? patchSize_
                                                                                                 : resolvePatchSize(scene_));
  }
}

void RenderCommand::checkImageOutputs() const {
  if (sensors_.active()) return;
  for (const auto& out : outputs_) {
    const auto dot = out.rfind('.');
    const std::string ext = dot == std::string::npos ? "" : out.substr(dot);
    if (ext != ".exr" && ext != ".png" && ext != ".EXR" && ext != ".PNG")
      throw InputError(out, "", "unsupported image type (expected .exr or .png)");
    const auto dir = std::filesystem::path(out).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) throw InputError(out, "", "the output folder does not exist");
  }
}

int RenderCommand::renderSensors() {  // sensors_.run preprocesses the integrator for the sensors' rays
  SensorOptions so;
  so.timeLimit = timeLimit_;
  so.seed = seed();
  so.threads = threads_;
  so.quiet = quiet_;
  so.sampler = samplerMode();
  so.comm = &comm_;
  if (photometric_.active())
    sensors_.onResults = [&](const auto& sets, const auto& values) {
      photometric_.writeGrid(sets, values, sensors_.daylightFactor);
    };
  const int rc = sensors_.run(*integrator_, *renderScene_, sensorSets_, outputs_, so);
  if (comm_.root()) integrators_.chosen().finish(*integrator_, nullptr, 0.0f, 0.0, quiet_);  // --cache-file, the record counts
  return rc;
}

int RenderCommand::runPreview() {
  PreviewOptions po;
  po.integrator = integrators_.name;
  po.integratorOptions = integratorOptions_;
  po.seed = seed();
  po.sampler = samplerMode();
  // Keys 1..n switch integrators: each is configured like the offline render's (the others' own
  // options are not given: their defaults).
  for (const auto& cli : integrators_.clis)
    if (cli.get() != &integrators_.chosen()) {
      IntegratorSetup setup{&app_, &scene_, po.seed, threads_, spp_, samplerMode(), quiet_};
      cli->configure(setup);
    }
  po.factory = [this](const std::string& name) { return integrators_.cli(name).make(integratorOptions_); };
  po.threads = threads_;
  po.spp = spp_ > 0 ? spp_ : scene_.settings.spp;
  po.frames = frames_;
  po.screenshot = screenshot_;
  po.windowGrab = windowGrab_;
  po.exposure = exposure_;
  po.quiet = quiet_;
  return firstshot::runPreview(*renderScene_, po);
}

int RenderCommand::renderImage() {
  RenderOptions ro;
  ro.spp = spp_ > 0 ? spp_ : scene_.settings.spp;
  ro.seed = seed();
  ro.sampler = samplerMode();
  ro.adaptive = adaptiveRender();
  ro.threads = threads_;
  ro.quiet = quiet_;
  ro.comm = &comm_;
  const IntegratorCli& cli = integrators_.chosen();
  if (checkpoint_.active())
    checkpoint_.makeKey(app_, scenePath_, scene_, fsdPath_, integrators_.name, ro.seed, integratorOptions_.maxDepth,
                        cli.inputFile());
  for (auto& [name, value] : checkpoint_.key) {  // as used: --integrator auto may have chosen them
    if (name == integrator_option::kPatchNee) value = integrators_.patchNee;
    if (name == integrator_option::kShootFirstShot) value = integrators_.shootFirstShot;
    if (name == integrator_option::kLightSampler) value = integrators_.lightSampler;
    if (name == kRecordSamplesKey && cli.recordSamples() > 0) value = std::to_string(cli.recordSamples());
  }
  if (checkpoint_.active() && tableUnused_) checkpoint_.key.emplace_back(kTableUnusedKey, "unused");
  const auto preprocessStart = std::chrono::steady_clock::now();
  // A preprocessing sized wrong (the cache's fill, its growth projected short by the pilot) must not take the time:
  // it stops at three quarters of what is left, with what it made. Not with a checkpoint: a resumed render must fill
  // alike.
  if (timeLimit_ > 0 && !checkpoint_.active())
    integrator_->limitPreprocessSeconds(std::max(1e-3, kFillTimeShare * (timeLimit_ - pilotSeconds_)));
  integrator_->preprocess(*renderScene_);
  // --time is the whole budget: the pilot's time and the integrator's preprocessing (the irradiance cache's fill, light
  // trees) come off it; at least one pass is rendered.
  const double preprocessSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - preprocessStart).count();
  ro.timeLimit = timeLimit_ > 0 ? std::max(1e-3, timeLimit_ - pilotSeconds_ - preprocessSeconds) : 0.0;

  const Camera camera(scene_.camera);
  Film film(camera.width(), camera.height());
  RenderStats st;
  try {
    st = checkpoint_.render(*integrator_, camera, film, ro);
    throwIfInterrupted("no output written");
    if (!comm_.root()) return 0;  // rank 0's film holds every rank's pixels; it alone writes
    const double cdPerW = photometric_.units == "luminance" ? sensors_.efficacy : 0.0;  // cd/m² per W/(m² sr)
    for (const auto& out : outputs_) film.write(out, aov_, exposure_, cdPerW);
    if (photometric_.active()) photometric_.writeImage(film, sensors_.efficacy);
    cli.finish(*integrator_, &film, exposure_, st.seconds, quiet_);
  } catch (const Interrupted& e) {
    throw checkpoint_.saveAfterInterrupt(e, film);
  }
  checkpoint_.finished();

  if (st.nonFinite > 0)
    fmt::print(stderr, "firstshot-render: warning: {} samples were NaN or Inf and were recorded as 0\n", st.nonFinite);
  if (!quiet_) {
    const auto* t = renderScene_->firstShot();
    const EmbreeScene& traced = renderScene_->embree();
    fmt::print(stderr, "{}x{} at {} spp in {:.2f} s: {:.2f} Mrays/s; {} patches{}, {} lights ({} replaced by first-shot){}\n",
               camera.width(), camera.height(), st.spp, st.seconds, st.seconds > 0 ? st.rays / st.seconds * 1e-6 : 0.0,
               renderScene_->mesh().size(),
               traced.tracesFaces() ? fmt::format(" (traced as their {} faces)", traced.tracedPolygons()) : "",
               scene_.lights.size(), t ? t->replacedLights.size() : 0,
               comm_.size() > 1 ? fmt::format("; {} ranks, rank 0 sent {:.2f} MB", comm_.size(), comm_.bytesSent() / 1e6) : "");
  }
  return 0;
}

}  // namespace firstshot
