// firstshot-render: scene [+ first-shot table] -> image, with the Embree path tracer.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "common/cli.h"
#include "common/firstshot.h"
#include "common/interrupt.h"
#include "common/memory_limit.h"
#include "common/patch_size.h"
#include "common/scene_desc.h"
#include "render/camera.h"
#include "render/checkpoint_cli.h"
#include "render/falsecolor_cli.h"
#include "render/film.h"
#include "render/integrator.h"
#include "render/integrators/bundle/cli.h"
#include "render/integrators/irradiance_cache/cli.h"
#include "render/integrators/light/light_tracer.h"
#include "render/preview/preview_app.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "render/sensors_cli.h"

int main(int argc, char** argv) {
  FIRSTSHOT_TOOL_COMM(argc, argv, comm);  // MPI_COMM_WORLD in firstshot-render-mpi (docs/mpi.md)
  return fs::runTool("firstshot-render", comm, [&] {
    CLI::App app{"firstshot-render: renders a scene with the Embree path tracer, optionally replacing small lights "
                 "by their first-shot factors"};
    std::string scenePath, fsdPath, integratorName = "path", primary = "exact", lightSampler = "tree", patchNee = "off",
                lightVisibility = "on", shootFirstShot = "patches", tableVisibility = "on",
                samplerName = "independent";
    std::vector<std::string> outputs;
    int spp = 0, threads = 0, maxDepth = -1, width = 0, height = 0, lightPaths = 0;
    double timeLimit = 0, patchSize = 0;
    float exposure = 0;
    uint64_t seed = 0;
    bool quiet = false, aov = false;
    bool preview = false;      // --preview: the interactive window (render/preview/)
    int frames = -1;
    std::string screenshot, windowGrab;
    app.add_option("scene", scenePath, "scene file (.json, .obj, .gltf, .glb, .ply)")->required();
    app.add_option("--firstshot", fsdPath, "first-shot table from firstshot-preprocess (.fsd)");
    app.add_option("--integrator", integratorName, "integrator: path | irradiance-cache | light (light tracing, "
                                                   "docs/light-tracing.md) | bundle (ray-bundle stochastic iteration, "
                                                   "docs/bundle.md) | bdpt (bidirectional path tracing, "
                                                   "docs/bdpt.md)")->capture_default_str();
    app.add_option("--primary", primary, "with --firstshot, camera-visible surfaces: exact (shadow rays to small lights) "
                                         "or patch (first-shot there too)")
        ->check(CLI::IsMember({"exact", "patch"}))->capture_default_str();
    app.add_option("--light-sampler", lightSampler, "next-event estimation: tree (one light per vertex, chosen by a light "
                                                    "tree) or all (one sample of every light per vertex)")
        ->check(CLI::IsMember({"tree", "all"}))->capture_default_str();
    app.add_option("--patch-nee", patchNee, "with --firstshot: sample the lit first-shot patches as light sources at "
                                            "the first surface of a path (first), at every surface (every) or not (off)")
        ->check(CLI::IsMember({"first", "every", "off", "on"}))->capture_default_str();
    app.add_option("--light-visibility", lightVisibility, "light tree: weight its choices by the visibility of the "
                                                          "lights from each region, estimated with a few rays per region")
        ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
    app.add_option("--table-visibility", tableVisibility, "with --firstshot and --primary exact, camera-visible "
                                                          "surfaces: no shadow ray to a small point or spot light "
                                                          "the table finds visible from the whole patch or from none "
                                                          "of it (on), or shadow rays to all (off)")
        ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
    app.add_option("--shoot-firstshot", shootFirstShot, "light and bdpt with --firstshot: the small lights' particles "
                                                        "start from the patches the table lights (patches) or the "
                                                        "table is ignored (off; docs/light-tracing.md, docs/bdpt.md)")
        ->check(CLI::IsMember({"patches", "off"}))->capture_default_str();
    app.add_option("--light-paths", lightPaths, "light: light paths per pixel in each pass (0: automatic, 8 and at most "
                                                 "2^21 per pass, or 1 in scenes with mirrors or glass; "
                                                 "docs/light-tracing.md)")
        ->check(CLI::Range(0, 4096))->capture_default_str();
    auto* sppOpt = app.add_option("--spp", spp, "samples per pixel (default: the scene's settings.spp)")->check(CLI::Range(1, 1 << 30));
    app.add_option("--time", timeLimit, "render passes of 1 spp until this many seconds have passed (the image then "
                                        "depends on how many passes fit)")
        ->check(CLI::Range(1e-3, 1e9))->excludes(sppOpt);
    auto* outOpt = app.add_option("-o,--output", outputs, "output image, .exr (linear float) or .png (sRGB); may be repeated "
                                                          "(required without --preview)");
    app.add_option("--threads", threads, "worker threads (default: one per core); the image does not depend on it")
        ->check(CLI::Range(0, 4096));
    app.add_option("--seed", seed, "random seed (default: the scene's settings.seed)");
    app.add_option("--sampler", samplerName, "samples' numbers (every integrator, the sensors, the preview): independent "
                                             "(a hash per pixel, sample and dimension) or sobol (per pixel Owen-scrambled "
                                             "Sobol' pairs, stratified over the samples; common/rng.h)")
        ->check(CLI::IsMember({"independent", "sobol"}))->capture_default_str();
    app.add_option("--max-depth", maxDepth, "longest path in bounces (default: the scene's settings.max_depth)")
        ->check(CLI::Range(0, 1 << 30));
    app.add_option("--exposure", exposure, "PNG exposure in stops (scale by 2^exposure)");
    app.add_flag("--aov", aov, "EXR: add albedo and normal layers for external denoisers");
    app.add_option("--width", width, "image width (default: the scene's camera)")->check(CLI::Range(1, 1 << 16));
    app.add_option("--height", height, "image height (default: the scene's camera)")->check(CLI::Range(1, 1 << 16));
    app.add_option("--patch-size", patchSize, "without --firstshot: longest patch edge in metres (default: every face as it is; --integrator bundle: "
                                         "the scene's patch_size, else automatic as the preprocessor's)")
        ->check(CLI::Range(1e-6, 1e6));
    app.add_flag("-q,--quiet", quiet, "no progress bar or summary");
    auto* previewOpt = app.add_flag("--preview", preview, "open the interactive preview window (needs a display; keys: H)")
                           ->excludes(outOpt);
    app.add_option("--frames", frames, "with --preview: scripted run: refine for this many frames (1 spp each; the image "
                                       "then equals an offline render with --spp frames), save --screenshot, exit")
        ->check(CLI::Range(0, 1 << 30))->needs(previewOpt);
    app.add_option("--screenshot", screenshot, "with --preview: screenshot file OUT.png (OUT.exr is written beside it); "
                                               "key P saves OUT-NNN.png")
        ->needs(previewOpt);
    app.add_option("--window-grab", windowGrab, "with --preview --frames: save the window's pixels as shown (.png), for tests")
        ->needs(previewOpt);
    fs::IrradianceCacheCli irradianceCache;  // --accuracy, --bounces, --cache-file, ... (render/integrators/irradiance_cache/cli.h)
    irradianceCache.add(app);
    fs::BundleCli bundle;  // --iterations, --bundle-resolution, --bundle-directions (render/integrators/bundle/cli.h)
    bundle.add(app);
    fs::CheckpointCli checkpoint;  // --checkpoint, --checkpoint-file, --resume (render/checkpoint_cli.h)
    checkpoint.add(app);
    fs::SensorsCli sensors;  // --sensors, --grid, --samples, --efficacy (render/sensors_cli.h)
    sensors.add(app);
    fs::FalseColorCli photometric;  // --units, --falsecolor, --falsecolor-* (render/falsecolor_cli.h)
    photometric.add(app);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app.exit(e) == 0 ? 0 : fs::kExitBadInput;
    }
    // SIGINT/SIGTERM: stop, write no image (a checkpoint with --checkpoint), exit 130/143 (docs/robustness.md).
    if (!preview) fs::installInterruptHandlers();

    sensors.checkOptions(app, outputs);
    std::vector<fs::SensorSet> sensorSets = sensors.sets();  // --grid-quad sets join once the scene is loaded
    photometric.checkOptions(app, sensors.active(), sensorSets, outputs);
    if (!preview && outputs.empty()) throw fs::InputError("", "--output", "an output image is required (or use --preview)");
    if (comm.size() > 1)  // docs/mpi.md: what is split over ranks
      for (const char* option : {"--preview", "--checkpoint", "--resume"})
        if (app.count(option))
          throw fs::InputError("", option, fmt::format("not available in an MPI run of {} ranks (run it with one)", comm.size()));
    quiet = quiet || !comm.root();  // rank 0 shows progress and prints the results
    if (preview && app.count("--time")) throw fs::InputError("", "--time", "not available with --preview (use --spp)");
    for (const std::string* png : {&screenshot, &windowGrab}) {
      if (png->empty()) continue;
      const std::string ext = std::filesystem::path(*png).extension().string();
      if (ext != ".png" && ext != ".PNG") throw fs::InputError(*png, "", "the screenshot must be a .png file");
      const auto dir = std::filesystem::path(*png).parent_path();
      if (!dir.empty() && !std::filesystem::is_directory(dir)) throw fs::InputError(*png, "", "the output folder does not exist");
    }

    fs::SceneDesc scene = fs::loadScene(scenePath);
    sensors.addQuadGrids(scene, sensorSets);  // --grid-quad: on the scene's quads
    if (width > 0) scene.camera.width = width;
    if (height > 0) scene.camera.height = height;
    if (!preview && !sensors.active()) fs::Film::requireFits(scene.camera.width, scene.camera.height, scene.file);  // before any other work
    fs::IntegratorOptions io;
    io.maxDepth = maxDepth >= 0 ? maxDepth : scene.settings.maxDepth;
    // A sensor is a camera-visible point (vertex 0): its cosine rays' first hits are bounce 1.
    if (sensors.active()) io.maxDepth = std::max(0, io.maxDepth - 1);
    io.primary = primary == "patch" ? fs::PrimaryMode::Patch : fs::PrimaryMode::Exact;
    io.lightSampler = lightSampler == "all" ? fs::LightStrategy::All : fs::LightStrategy::Tree;
    io.patchNee = patchNee == "off" ? fs::PatchNee::Off : patchNee == "first" ? fs::PatchNee::First : fs::PatchNee::Every;
    io.lightVisibility = lightVisibility == "on";
    io.tableVisibility = tableVisibility == "on";
    io.shootFromPatches = shootFirstShot == "patches";
    io.lightPathsPerPixel = lightPaths;
    if (integratorName == "light" && lightPaths > 0)
      fs::requireMemory(double(lightPaths) * scene.camera.width * scene.camera.height *
                            fs::LightTracingIntegrator::kSplatBytesPerPath, "",
                        "--light-paths", fmt::format("the splats of {} light paths per pixel", lightPaths),
                        "lower --light-paths");
    io.comm = &comm;
    auto integrator = fs::makeIntegrator(integratorName, io);
    const fs::SamplerMode samplerMode = samplerName == "sobol" ? fs::SamplerMode::Sobol : fs::SamplerMode::Independent;
    irradianceCache.settings.sampler = samplerMode;  // the two-pass fill traces the render's camera samples
    irradianceCache.configure(*integrator, app.count("--seed") ? seed : scene.settings.seed, threads);
    bundle.configure(*integrator, spp, app);
    checkpoint.configure(app, outputs, *integrator);
    if (sensors.active()) fs::requireSensorIntegrator(*integrator);
    for (const auto& out : sensors.active() ? std::vector<std::string>() : outputs) {  // reject a bad output name before the render, not after
      const auto dot = out.rfind('.');
      const std::string ext = dot == std::string::npos ? "" : out.substr(dot);
      if (ext != ".exr" && ext != ".png" && ext != ".EXR" && ext != ".PNG")
        throw fs::InputError(out, "", "unsupported image type (expected .exr or .png)");
      const auto dir = std::filesystem::path(out).parent_path();
      if (!dir.empty() && !std::filesystem::is_directory(dir)) throw fs::InputError(out, "", "the output folder does not exist");
    }

    std::optional<fs::RenderScene> rs;
    if (!fsdPath.empty())
      rs.emplace(scene, fs::readFirstShot(fsdPath, fs::hashScene(scene)), fsdPath);
    else
      rs.emplace(scene, patchSize > 0 || integratorName != "bundle" ? patchSize : fs::resolvePatchSize(scene));
    if (sensors.active()) {  // sensors.run preprocesses the integrator for the sensors' rays
      fs::SensorOptions so;
      so.timeLimit = timeLimit;
      so.seed = app.count("--seed") ? seed : scene.settings.seed;
      so.threads = threads;
      so.quiet = quiet;
      so.lightSampler = io.lightSampler;
      so.sampler = samplerMode;
      so.comm = &comm;
      if (photometric.active())
        sensors.onResults = [&](const auto& sets, const auto& lux) { photometric.writeGrid(sets, lux); };
      const int rc = sensors.run(*integrator, *rs, sensorSets, outputs, so);
      if (comm.root()) irradianceCache.finish(*integrator, nullptr, 0.0f, 0.0, quiet);  // --cache-file, the record counts
      return rc;
    }
    if (preview) {
      fs::PreviewOptions po;
      po.integrator = integratorName;
      po.integratorOptions = io;
      po.seed = app.count("--seed") ? seed : scene.settings.seed;
      po.sampler = samplerMode;
      // Keys 1..n switch integrators: each is configured like the offline render's.
      po.factory = [io, ic = irradianceCache, bs = bundle.settings, seed = po.seed, threads](const std::string& name) mutable {
        auto made = fs::makeIntegrator(name, io);
        if (dynamic_cast<fs::IrradianceCacheIntegrator*>(made.get())) ic.configure(*made, seed, threads);
        if (auto* b = dynamic_cast<fs::BundleIntegrator*>(made.get())) b->setSettings(bs);
        return made;
      };
      po.threads = threads;
      po.spp = spp > 0 ? spp : scene.settings.spp;
      po.frames = frames;
      po.screenshot = screenshot;
      po.windowGrab = windowGrab;
      po.exposure = exposure;
      po.quiet = quiet;
      return fs::runPreview(*rs, po);
    }
    fs::RenderOptions ro;
    ro.spp = spp > 0 ? spp : scene.settings.spp;
    ro.timeLimit = timeLimit;
    ro.seed = app.count("--seed") ? seed : scene.settings.seed;
    ro.sampler = samplerMode;
    ro.threads = threads;
    ro.quiet = quiet;
    ro.comm = &comm;
    if (checkpoint.active())
      checkpoint.makeKey(app, scenePath, scene, fsdPath, integratorName, ro.seed, io.maxDepth, irradianceCache.settings.cacheFile);
    integrator->preprocess(*rs);

    const fs::Camera camera(scene.camera);
    fs::Film film(camera.width(), camera.height());
    fs::RenderStats st;
    try {
      st = checkpoint.render(*integrator, camera, film, ro);
      fs::throwIfInterrupted("no output written");
      if (!comm.root()) return 0;  // rank 0's film holds every rank's pixels; it alone writes
      const double cdPerW = photometric.units == "luminance" ? sensors.efficacy : 0.0;  // cd/m² per W/(m² sr)
      for (const auto& out : outputs) film.write(out, aov, exposure, cdPerW);
      if (photometric.active()) photometric.writeImage(film, sensors.efficacy);
      irradianceCache.finish(*integrator, &film, exposure, st.seconds, quiet);
    } catch (const fs::Interrupted& e) {
      throw checkpoint.saveAfterInterrupt(e, film);
    }
    checkpoint.finished();

    if (st.nonFinite > 0)
      fmt::print(stderr, "firstshot-render: warning: {} samples were NaN or Inf and were recorded as 0\n", st.nonFinite);
    if (!quiet) {
      const auto* t = rs->firstShot();
      fmt::print(stderr, "{}x{} at {} spp in {:.2f} s: {:.2f} Mrays/s; {} patches, {} lights ({} replaced by first-shot){}\n",
                 camera.width(), camera.height(), st.spp, st.seconds, st.seconds > 0 ? st.rays / st.seconds * 1e-6 : 0.0,
                 rs->mesh().size(), scene.lights.size(), t ? t->replacedLights.size() : 0,
                 comm.size() > 1 ? fmt::format("; {} ranks, rank 0 sent {:.2f} MB", comm.size(), comm.bytesSent() / 1e6) : "");
    }
    return 0;
  });
}
