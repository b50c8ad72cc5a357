// firstshot-preprocess: scene -> patches -> first-shot table (.fsd).
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <tbb/global_control.h>

#include <optional>

#include "common/formats/load_scene.h"
#include "common/patches/patch_size.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "common/util/cli.h"
#include "common/util/interrupt.h"
#include "preprocess/gl/gl_device_option.h"
#include "preprocess/preprocessor.h"
#include "preprocess/profile.h"

namespace {

void printStats(const firstshot::SceneDesc& scene, const std::string& path, double ps, bool automatic) {
  const firstshot::PatchMesh mesh = firstshot::buildPatches(scene, ps);
  size_t quads = 0;
  double minA = 1e300, maxA = 0;
  for (const auto& p : mesh.patches) {
    quads += p.count == 4;
    minA = std::min(minA, p.area), maxA = std::max(maxA, p.area);
  }
  fmt::print("scene        {}\n", path);
  fmt::print("shapes       {}\nmaterials    {}\nlights       {}\n", scene.shapes.size(), scene.materials.size(), scene.lights.size());
  fmt::print("patch size   {:.6g} m{}\npatches      {} ({} quads, {} triangles)\n", ps,
             !automatic ? std::string() : fmt::format(" (automatic: the faces cut into at most {} more patches)", firstshot::kAutoPatchBudget), mesh.size(),
             quads, mesh.size() - quads);
  fmt::print("area         {:.6f} m² (patch min {:.3e}, max {:.3e})\n", mesh.totalArea(), mesh.size() ? minA : 0.0, maxA);
  fmt::print("patch hash   {:016x}\nscene hash   {:016x}\n", firstshot::hashPatches(mesh), firstshot::hashScene(scene));
}

void dumpCsv(const std::string& path) {
  const firstshot::FirstShotTable t = firstshot::readFirstShot(path);
  fmt::print("patch,v0x,v0y,v0z,v1x,v1y,v1z,v2x,v2y,v2z,v3x,v3y,v3z,area,nx,ny,nz,sample,sx,sy,sz,r\n");
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const firstshot::Patch& p = t.mesh.patches[j];
    std::string verts;
    for (uint32_t k = 0; k < 4; ++k)
      verts += k < p.count ? fmt::format("{:.9g},{:.9g},{:.9g},", p.v[k].x, p.v[k].y, p.v[k].z) : std::string(",,,");
    for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k) {
      const firstshot::LightSample& s = t.samples[t.sampleIndex[k]];
      fmt::print("{},{}{:.9g},{:.9g},{:.9g},{:.9g},{},{:.9g},{:.9g},{:.9g},{:.9g}\n", j, verts, p.area, p.normal.x,
                 p.normal.y, p.normal.z, t.sampleIndex[k], s.position.x, s.position.y, s.position.z, t.factor[k]);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  FIRSTSHOT_TOOL_COMM(argc, argv, comm);  // MPI_COMM_WORLD in firstshot-preprocess-mpi (docs/mpi.md)
  firstshot::installInterruptHandlers();  // SIGINT/SIGTERM: stop, write nothing, exit 130/143 (common/util/interrupt.h)
  return firstshot::runTool("firstshot-preprocess", comm, [&] {
    CLI::App app{"firstshot-preprocess: computes the first-shot factors of a scene's small lights (.fsd)"};
    std::string scenePath, out, dump, gl = "osmesa";
    firstshot::SettingsOverrides cli;  // the settings given here; the scene's (or their defaults) for the rest
    double timeLimit = 0;
    int threads = 0;
    bool stats = false, quiet = false;
    std::string glReduce = "auto";  // --gl-reduce
    app.add_option("scene", scenePath, "scene file (.json, .obj, .gltf, .glb, .ply)");
    app.add_option("-o,--output", out, "the first-shot file to write (.fsd)");
    app.add_option("--resolution", cli.resolution, "R: pixels across a full cube face (default: settings.item_buffer_resolution)")
        ->check(CLI::Range(2, 8192));
    app.add_option("--window", cli.window, "area-light window: hemicube | tetra (default: settings.window)")
        ->check(CLI::IsMember({"hemicube", "tetra"}));
    app.add_option("--backend", cli.backend, "item buffers: gl (rasterised) | embree (ray cast) | auto (per light: gl while the scene has at most 1/12 as many triangles as the light's window has pixels, else embree); a scene with alpha cut-outs takes embree unless gl is asked for")
        ->check(CLI::IsMember({"gl", "embree", "auto"}));
    app.add_option("--gl", gl, "OpenGL platform: osmesa (no display needed) | egl (a GPU through EGL's device platform if there is one, else Mesa's surfaceless platform)")->check(CLI::IsMember({"osmesa", "egl"}));
    std::string glDevice;  // --gl-device (preprocess/gl/gl_device_option.h)
    app.add_option("--gl-device", glDevice, "EGL device (implies --gl egl): N (an index that 'list' shows) | auto (default: the first GPU, else Mesa's surfaceless platform) | list (print the devices and exit)");
    app.add_option("--gl-reduce", glReduce, "GL back end: reduce the item buffers on the cpu (read back) | gpu (compute shaders, only per-patch sums read back) | auto (gpu unless the GL renderer is llvmpipe or softpipe; default)")
        ->check(CLI::IsMember({"cpu", "gpu", "auto"}));
    app.add_option("--patch-size", cli.patchSize, "longest patch edge in metres (default: settings.patch_size, else automatic from the scene's faces)")->check(CLI::PositiveNumber);
    app.add_option("--light-patch-size", cli.lightPatchSize, "area-light tessellation in metres (default: settings.light_patch_size)")
        ->check(CLI::PositiveNumber);
    app.add_option("--min-patch-size", cli.minPatchSize, "smallest patch edge adaptive refinement may reach, m (default: settings.min_patch_size)")
        ->check(CLI::PositiveNumber);
    app.add_option("--refine-tolerance", cli.refineTolerance, "split patches whose shadow-edge measure exceeds this fraction of their irradiance (default: settings.refine_tolerance)")
        ->check(CLI::PositiveNumber);
    app.add_option("--light-tolerance", cli.lightTolerance, "automatic area-light tessellation: relative error at the nearest receiver (default: settings.light_tolerance)")
        ->check(CLI::PositiveNumber);
    app.add_option("--threads", threads, "workers, one GL context each, and the cap on every parallel loop "
                                         "(default: one per core)")->check(CLI::NonNegativeNumber);
    app.add_option("--seed", cli.rotationSeed, "0: windows aligned with each light's frame; else rotate each sample's window randomly about its axis (not an IES light's: its table fixes the frame)");
    app.add_option("--time", timeLimit, "give up (writing nothing) after this many seconds")->check(CLI::NonNegativeNumber);
    app.add_option("--estimator", cli.estimator, "analytic: closed form times the visible fraction (default) | pixels: plain pixel sums")
        ->check(CLI::IsMember({"analytic", "pixels"}));
    std::string luminaires = "auto";
    uint64_t luminaireParticles = firstshot::LuminaireOptions().particles;
    app.add_option("--luminaires", luminaires, "luminaires (lights and what surrounds them, traced once to their box's exit surfaces): auto (the scene's named ones and those detected: lights mostly inside glass or close to what they light; default) | named (only the scene's \"luminaire\" names) | off")
        ->check(CLI::IsMember({"auto", "named", "off"}));
    app.add_option("--luminaire-particles", luminaireParticles, "particles traced for all luminaires together, shared by their power, at least 65536 each (default 4194304)")
        ->check(CLI::Range(uint64_t(1), uint64_t(1) << 40));
    app.add_option("--dump-csv", dump, "print one CSV row per non-zero factor of an .fsd file and exit");
    app.add_flag("--stats", stats, "load the scene, build the patches, print their statistics and exit");
    app.add_flag("-q,--quiet", quiet, "no progress bar");
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app.exit(e) == 0 ? 0 : firstshot::kExitBadInput;
    }
    if (!glDevice.empty() && firstshot::applyGLDeviceOption(glDevice, gl, app.count("--gl") > 0)) return 0;  // "list"
    if (!dump.empty()) {
      if (comm.root()) dumpCsv(dump);
      return 0;
    }
    if (scenePath.empty()) throw firstshot::InputError("", "command line", "no scene file given (see --help)");
    const firstshot::SceneDesc scene = firstshot::loadScene(scenePath);
    firstshot::PreprocessOptions o;
    o.settings = firstshot::resolveSettings(scene, cli);  // the scene's settings, the command line's on top, resolved
    o.gl = gl, o.threads = threads, o.quiet = quiet || !comm.root(), o.timeLimit = timeLimit;
    o.comm = &comm;
    o.glReduce = glReduce;
    o.luminaires.mode = luminaires, o.luminaires.particles = luminaireParticles;
    if (stats) {
      if (comm.root()) printStats(scene, scenePath, o.settings.patchSize, !cli.patchSize && !(scene.settings.patchSize > 0));
      return 0;
    }
    if (out.empty()) throw firstshot::InputError("", "command line", "no output file given (-o OUT.fsd)");
    // --threads caps every parallel loop as well (TBB's, and Embree's BVH builds), not only the workers.
    std::optional<tbb::global_control> cap;
    if (threads > 0) cap.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
    firstshot::PreprocessStats st;
    const firstshot::FirstShotTable table = firstshot::preprocessScene(scene, o, &st);
    if (!comm.root()) return 0;  // every rank holds the table; rank 0 writes it
    {
      firstshot::profile::Scope writeTime(firstshot::profile::Write);
      firstshot::writeFirstShot(out, table);
    }
    if (firstshot::profile::enabled()) firstshot::profile::report(stderr);
    for (size_t i = 0; i < table.luminaires.size(); ++i)
      fmt::print("{}\n", firstshot::luminaireSummary(table.luminaires[i], i < st.luminaireSeconds.size() ? st.luminaireSeconds[i] : 0.0));
    const std::string ranks = comm.size() == 1 ? std::string()
                                               : fmt::format("; {} ranks, rank 0 sent {:.2f} MB in {:.2f} s of exchanges", comm.size(),
                                                             st.bytesSent / 1e6, st.exchangeSeconds);
    fmt::print("{}: {} light samples ({} small lights, {} large), {} patches, {} non-zero factors, {:.2f} s, {:.1f} samples/s [{}; R = {}{}]\n",
               out, st.lightSamples, st.smallLights, st.largeLights, st.patches, st.nonZeros, st.seconds,
               st.seconds > 0 ? st.lightSamples / st.seconds : 0.0, st.renderer, o.settings.resolution, ranks);
    return 0;
  });
}
