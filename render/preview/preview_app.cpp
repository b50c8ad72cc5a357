// The preview application: window, instant picture, progressive refinement, input.
#include "render/preview/preview_app.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "render/output/film.h"
#include "render/output/image_io.h"
#include "render/preview/gl_raster.h"
#include "render/preview/gl_window.h"
#include "render/preview/orbit_camera.h"
#include "render/preview/progressive.h"
#include "render/preview/raster_mesh.h"

namespace firstshot {

std::string previewKeyHelp() {
  std::string s =
      "firstshot-render preview: mouse: left drag orbit, middle or shift+left drag pan, right drag or wheel dolly\n"
      "  W A S D  fly forward / left / back / right\n";
  const std::vector<std::string> names = integratorNames();
  for (size_t i = 0; i < names.size() && i < 9; ++i) s += fmt::format("  {}        integrator {}\n", i + 1, names[i]);
  s +=
      "  F        first-shot on / off (with --firstshot)\n"
      "  I        instant picture only (no refinement shown)\n"
      "  E        patch edges\n"
      "  R        irradiance-cache records\n"
      "  + / -    exposure up / down half a stop\n"
      "  P        screenshot (.png and .exr)\n"
      "  C        print the camera as scene-file JSON\n"
      "  H, F1    this list\n"
      "  Esc, Q   quit\n";
  return s;
}

std::string cameraJson(const CameraDesc& c) {
  auto v = [](const Vec3d& p) { return fmt::format("[{}, {}, {}]", p.x, p.y, p.z); };
  return fmt::format("\"camera\": {{\"position\": {}, \"look_at\": {}, \"up\": {}, \"fov_y\": {}, \"resolution\": [{}, {}]}}",
                     v(c.position), v(c.lookAt), v(c.up), c.fovYDeg, c.width, c.height);
}

namespace {

class PreviewApp {
 public:
  PreviewApp(const RenderScene& scene, const PreviewOptions& options)
      : options_(options),
        tableScene_(scene.firstShot() ? &scene : nullptr),
        plainScene_(scene.firstShot() ? nullptr : &scene),
        camera_(scene.desc().camera),
        integrator_(options.integrator),
        exposure_(options.exposure),
        window_(openWindow(scene.desc().camera)),
        raster_(),
        progressive_(factory(options), options.seed, options.threads,
                     options.frames >= 0 ? options.frames : std::max(1, options.spp), options.sampler) {
    Vec3d lo, hi;
    scene.desc().bounds(lo, hi);
    diagonal_ = std::max(1e-3, glm::length(hi - lo));
    useFirstShot_ = tableScene_ != nullptr;
    if (!options_.quiet) fmt::print(stderr, "firstshot-render: preview on {}\n", window_->description());
  }

  int run() {
    rebuildMesh();
    restart();
    if (options_.frames >= 0) return runScripted();
    if (!options_.quiet) fmt::print("{}", previewKeyHelp());
    std::fflush(stdout);
    while (!window_->shouldClose()) {
      window_->pollEvents(flying() ? 0.0 : 1.0 / 60.0);
      bool moved = handleEvents();
      moved = fly() || moved;
      if (moved) restart();
      if (progressive_.poll(snapshot_)) onSnapshot();
      int fw = 0, fh = 0;
      window_->framebufferSize(fw, fh);
      if (fw != fbWidth_ || fh != fbHeight_) fbWidth_ = fw, fbHeight_ = fh, dirty_ = true;
      if (dirty_) draw();
      if (std::exchange(swapPending_, false)) window_->swapBuffers();
      updateTitle(false);
    }
    return 0;
  }

 private:
  static IntegratorFactory factory(const PreviewOptions& o) {
    if (o.factory) return o.factory;
    return [io = o.integratorOptions](const std::string& name) { return makeIntegrator(name, io); };
  }

  static std::unique_ptr<GLWindow> openWindow(const CameraDesc& c) {
    try {
      return std::make_unique<GLWindow>(c.width, c.height, "firstshot-render preview");
    } catch (const DisplayError& e) {
      throw std::runtime_error(std::string("--preview needs a display (") + e.what() +
                               "); use xvfb-run or render offline with -o");
    }
  }

  const RenderScene& activeScene() {
    if (useFirstShot_ && tableScene_) return *tableScene_;
    if (!plainScene_) {
      // First-shot switched off: the same scene and patch size, every light sampled by NEE.
      ownedPlain_ = std::make_unique<RenderScene>(tableScene_->desc(), tableScene_->mesh().patchSize);
      plainScene_ = ownedPlain_.get();
    }
    return *plainScene_;
  }

  /// Starts refinement for the current camera, integrator and scene, and redraws the instant picture.
  void restart() {
    ProgressiveJob job;
    job.scene = &activeScene();
    job.integrator = integrator_;
    job.camera = camera_.desc();
    generation_ = progressive_.submit(job);
    raster_.renderInstant(camera_.desc());
    dirty_ = true;
  }

  void rebuildMesh() {
    const RasterMesh mesh = buildRasterMesh(activeScene(), useFirstShot_);
    raster_.setMesh(mesh);
  }

  void onSnapshot() {
    if (!snapshot_.error.empty()) {
      fmt::print(stderr, "firstshot-render: error: {}\n", snapshot_.error);
      return;
    }
    if (snapshot_.generation != generation_ || snapshot_.spp == 0) return;
    raster_.uploadFilm(snapshot_.rgb, snapshot_.width, snapshot_.height);
    if (snapshot_.hasRecords) raster_.setRecords(recordCircles(snapshot_.records));
    dirty_ = true;
  }

  bool showingFilm() const {
    return !instantOnly_ && snapshot_.generation == generation_ && snapshot_.spp > 0 && snapshot_.error.empty();
  }

  void draw() {
    DisplaySettings ds;
    ds.showFilm = showingFilm();
    ds.exposure = exposure_;
    ds.edges = edges_;
    ds.records = records_ && snapshot_.hasRecords;
    raster_.display(fbWidth_, fbHeight_, ds);
    dirty_ = false;
    swapPending_ = true;
  }

  void updateTitle(bool force) {
    const double now = window_->time();
    if (!force && now - lastTitle_ < 0.25) return;
    lastTitle_ = now;
    std::string status;
    const bool current = snapshot_.generation == generation_;
    if (current && !snapshot_.error.empty())
      status = "error: " + snapshot_.error;
    else if (current && snapshot_.spp > 0)
      status = fmt::format("{}/{} spp, {:.1f} s, {:.2f} Mrays/s", snapshot_.spp, progressive_.maxSpp(), snapshot_.seconds,
                           snapshot_.seconds > 0 ? snapshot_.rays / snapshot_.seconds * 1e-6 : 0.0);
    else
      status = "instant picture, refining";
    const std::string title =
        fmt::format("firstshot-render — {}{} — {} — EV {:+.1f}", integrator_,
                    tableScene_ ? (useFirstShot_ ? " + first-shot" : " (first-shot off)") : "", status, exposure_);
    if (title != title_) window_->setTitle(title_ = title);
  }

  /// Applies the queued input; returns true if the camera moved.
  bool handleEvents() {
    bool moved = false;
    InputEvent e;
    while (window_->nextEvent(e)) {
      switch (e.type) {
        case InputEvent::Type::Key: moved = onKey(e.key) || moved; break;
        case InputEvent::Type::MouseDown:
          drag_ = e.button == 0 ? (e.shift ? Drag::Pan : Drag::Orbit) : e.button == 2 ? Drag::Pan : Drag::Dolly;
          break;
        case InputEvent::Type::MouseUp: drag_ = Drag::None; break;
        case InputEvent::Type::MouseMove: {
          const double dx = e.x - cursorX_, dy = e.y - cursorY_;
          cursorX_ = e.x, cursorY_ = e.y;
          if (drag_ == Drag::Orbit) camera_.orbit(dx * 0.008, -dy * 0.008);
          if (drag_ == Drag::Pan) camera_.pan(dx, dy, std::max(1, fbHeight_));
          if (drag_ == Drag::Dolly) camera_.dolly(-dy * 0.05, diagonal_ * 1e-3);
          moved = moved || (drag_ != Drag::None && (dx != 0 || dy != 0));
          break;
        }
        case InputEvent::Type::Scroll:
          camera_.dolly(e.y, diagonal_ * 1e-3);
          moved = true;
          break;
      }
    }
    std::fflush(stdout);  // key messages show at once even when stdout is a file
    return moved;
  }

  bool flying() const {
    for (int k : {'W', 'A', 'S', 'D'})
      if (window_->keyDown(k)) return true;
    return false;
  }

  /// WASD: moves at half the scene's diagonal per second; returns true if the camera moved.
  bool fly() {
    const double now = window_->time(), dt = std::min(0.1, now - lastFly_);
    lastFly_ = now;
    const double f = double(window_->keyDown('W')) - double(window_->keyDown('S'));
    const double r = double(window_->keyDown('D')) - double(window_->keyDown('A'));
    if (f == 0 && r == 0) return false;
    const double step = 0.5 * diagonal_ * dt;
    camera_.fly(f * step, r * step, 0.0);
    return true;
  }

  /// Returns true if the camera or the job changed (a restart is needed).
  bool onKey(int key) {
    const std::vector<std::string> names = integratorNames();
    if (key >= '1' && key <= '9') {
      const size_t i = size_t(key - '1');
      if (i >= names.size()) {
        fmt::print("integrator {}: none (keys 1..{})\n", i + 1, names.size());
        return false;
      }
      if (names[i] == integrator_) return false;
      integrator_ = names[i];
      fmt::print("integrator: {}\n", integrator_);
      return true;
    }
    switch (key) {
      case 'F':
        if (!tableScene_) {
          fmt::print("first-shot: no table loaded (use --firstshot F.fsd)\n");
          return false;
        }
        useFirstShot_ = !useFirstShot_;
        fmt::print("first-shot: {}\n", useFirstShot_ ? "on" : "off");
        rebuildMesh();
        return true;
      case 'I': instantOnly_ = !instantOnly_; break;
      case 'E': edges_ = !edges_; break;
      case 'R':
        if (!snapshot_.hasRecords) {
          fmt::print("records: integrator {} has none\n", integrator_);
          return false;
        }
        records_ = !records_;
        fmt::print("records: {} ({} shown)\n", records_ ? "on" : "off", snapshot_.records.size());
        break;
      case '+': exposure_ += 0.5f; break;
      case '-': exposure_ -= 0.5f; break;
      case 'P': screenshot(nextScreenshotName()); break;
      case 'C': fmt::print("{}\n", cameraJson(camera_.desc())); break;
      case 'H':
      case InputEvent::kKeyF1: fmt::print("{}", previewKeyHelp()); break;
      case 'Q':
      case InputEvent::kKeyEscape: window_->requestClose(); break;
      default: return false;
    }
    dirty_ = true;
    return false;
  }

  std::string nextScreenshotName() {
    std::filesystem::path base = options_.screenshot.empty() ? "firstshot-preview.png" : options_.screenshot;
    const std::string stem = (base.parent_path() / base.stem()).string();
    return fmt::format("{}-{:03}.png", stem, ++screenshotCount_);
  }

  /// Saves @p pngPath and the same image as linear EXR beside it: the film when it has samples
  /// for the current view, else the instant picture.
  void screenshot(const std::string& pngPath) {
    int spp = 0;
    uint64_t gen = 0;
    Film film = progressive_.film(spp, gen);
    if (spp == 0 || gen != generation_ || instantOnly_) {
      int w = 0, h = 0;
      const std::vector<float> rgb = raster_.readInstant(w, h);
      film = Film(w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const float* p = &rgb[(size_t(y) * size_t(w) + size_t(x)) * 3];
          film.add(x, y, Color(p[0], p[1], p[2]), Color(0.0f), Vec3(0.0f));
        }
      spp = 0;
    }
    const std::string exrPath = std::filesystem::path(pngPath).replace_extension(".exr").string();
    film.write(pngPath, false, exposure_);
    film.write(exrPath, false);
    fmt::print("screenshot: {} and {} ({})\n", pngPath, exrPath, spp > 0 ? fmt::format("{} spp", spp) : "instant picture");
    std::fflush(stdout);
  }

  /// --frames N: the instant picture, then one frame per pass until N spp, the window grab and
  /// the screenshot.
  int runScripted() {
    window_->setSwapInterval(0);
    window_->framebufferSize(fbWidth_, fbHeight_);
    draw();
    auto done = [&] { return snapshot_.generation == generation_ && snapshot_.spp >= options_.frames; };
    while (options_.frames > 0 && !done()) {
      window_->swapBuffers();  // shows the previous frame
      const bool current = snapshot_.generation == generation_;
      progressive_.waitFor(current ? std::min(options_.frames, snapshot_.spp + 1) : 1);
      window_->pollEvents();
      if (progressive_.poll(snapshot_)) onSnapshot();
      if (!snapshot_.error.empty()) throw std::runtime_error(snapshot_.error);
      window_->framebufferSize(fbWidth_, fbHeight_);
      draw();
    }
    if (!options_.windowGrab.empty()) {  // the back buffer holds the last frame until the swap
      int w = 0, h = 0;
      const std::vector<uint8_t> rgb = raster_.readDisplay(w, h);
      image::writePng(options_.windowGrab, w, h, rgb.data());
    }
    window_->swapBuffers();
    updateTitle(true);
    if (!options_.screenshot.empty()) screenshot(options_.screenshot);
    if (!options_.quiet)
      fmt::print(stderr, "firstshot-render: preview: {} frames, {} spp in {:.2f} s ({:.2f} Mrays/s)\n", options_.frames,
                 snapshot_.spp, snapshot_.seconds, snapshot_.seconds > 0 ? snapshot_.rays / snapshot_.seconds * 1e-6 : 0.0);
    return 0;
  }

  enum class Drag { None, Orbit, Pan, Dolly };

  PreviewOptions options_;
  const RenderScene* tableScene_;  ///< the scene with its first-shot table, or nullptr
  const RenderScene* plainScene_;  ///< the scene without a table (built on demand when there is one)
  std::unique_ptr<RenderScene> ownedPlain_;
  OrbitCamera camera_;
  std::string integrator_;
  float exposure_;
  std::unique_ptr<GLWindow> window_;  // before everything that needs the GL context
  GLRaster raster_;
  ProgressiveRenderer progressive_;
  ProgressiveSnapshot snapshot_;
  uint64_t generation_ = 0;
  bool useFirstShot_ = false, instantOnly_ = false, edges_ = false, records_ = false;
  bool dirty_ = true, swapPending_ = false;
  int fbWidth_ = 0, fbHeight_ = 0;
  double diagonal_ = 1, cursorX_ = 0, cursorY_ = 0, lastFly_ = 0, lastTitle_ = -1;
  Drag drag_ = Drag::None;
  int screenshotCount_ = 0;
  std::string title_;
};

}  // namespace

int runPreview(const RenderScene& scene, const PreviewOptions& options) {
  PreviewApp app(scene, options);
  return app.run();
}

}  // namespace firstshot
