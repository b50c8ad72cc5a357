// The preview's background renderer: passes of one sample per pixel on a worker thread.
#include "render/preview/progressive.h"

#include <exception>

#include "render/scene/camera.h"
#include "render/loop/renderer.h"

namespace firstshot {

ProgressiveRenderer::ProgressiveRenderer(IntegratorFactory factory, uint64_t seed, int threads, int maxSpp,
                                         SamplerMode sampler)
    : factory_(std::move(factory)), seed_(seed), threads_(threads), maxSpp_(maxSpp), sampler_(sampler) {
  worker_ = std::thread([this] { run(); });
}

ProgressiveRenderer::~ProgressiveRenderer() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    cancel_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

uint64_t ProgressiveRenderer::submit(const ProgressiveJob& job) {
  uint64_t g;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = job;
    g = ++generation_;
    cancel_ = true;  // the worker clears it when it takes the job
  }
  wake_.notify_all();
  return g;
}

bool ProgressiveRenderer::poll(ProgressiveSnapshot& out) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (published_.generation == out.generation && published_.spp == out.spp && published_.error == out.error) return false;
  out = published_;
  return true;
}

void ProgressiveRenderer::waitFor(int spp) const {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait(lock, [&] {
    return stop_ || (published_.generation == generation_ && (published_.spp >= spp || !published_.error.empty()));
  });
}

Film ProgressiveRenderer::film(int& spp, uint64_t& generation) const {
  std::lock_guard<std::mutex> lock(filmMutex_);
  spp = filmSpp_;
  generation = filmGeneration_;
  return film_ ? *film_ : Film(1, 1);
}

void ProgressiveRenderer::run() {
  std::unique_ptr<Integrator> integrator;
  std::string integratorName;
  const RenderScene* integratorScene = nullptr;
  ProgressiveJob job;
  uint64_t gen = 0;
  int spp = 0;
  double seconds = 0;
  uint64_t rays = 0;
  bool failed = false;

  auto publish = [&](ProgressiveSnapshot&& snap) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (snap.generation == generation_) published_ = std::move(snap);
    }
    wake_.notify_all();
  };

  for (;;) {
    bool newJob = false;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != gen || (gen != 0 && spp < maxSpp_ && !failed); });
      if (stop_) return;
      if (generation_ != gen) {
        gen = generation_;
        job = job_;
        cancel_ = false;
        newJob = true;
      }
    }
    if (newJob) {
      spp = 0, seconds = 0, rays = 0, failed = false;
      try {
        if (!integrator || job.integrator != integratorName || job.scene != integratorScene) {
          integrator.reset();
          integrator = factory_(job.integrator);
          integrator->preprocess(*job.scene);
          integratorName = job.integrator, integratorScene = job.scene;
        }
      } catch (const std::exception& e) {
        integrator.reset();
        failed = true;
        ProgressiveSnapshot snap;
        snap.generation = gen;
        snap.error = job.integrator + ": " + e.what();
        publish(std::move(snap));
        continue;
      }
      std::lock_guard<std::mutex> lock(filmMutex_);
      film_ = std::make_unique<Film>(job.camera.width, job.camera.height);
      filmSpp_ = 0;
      filmGeneration_ = gen;
    }

    if (spp >= maxSpp_) continue;  // a job of 0 passes

    // One pass: sample index spp of every pixel.
    const Camera camera(job.camera);
    RenderOptions ro = RenderOptions::pass(spp, seed_);
    ro.sampler = sampler_;
    ro.threads = threads_;
    ro.quiet = true;
    ro.tileSize = 8;  // cancellation is checked per tile: small tiles follow the camera sooner (same image)
    ro.cancel = &cancel_;
    RenderStats st;
    {
      std::lock_guard<std::mutex> lock(filmMutex_);
      st = render(*integrator, camera, *film_, ro);
      if (st.cancelled) continue;  // a new job is waiting; this film is discarded
      filmSpp_ = ++spp;
    }
    seconds += st.seconds;
    rays += st.rays;

    // The film is only written by this thread: read it without the lock.
    ProgressiveSnapshot snap;
    snap.generation = gen;
    snap.spp = spp;
    snap.seconds = seconds;
    snap.rays = rays;
    snap.width = film_->width(), snap.height = film_->height();
    snap.rgb.resize(size_t(snap.width) * size_t(snap.height) * 3);
    for (int y = 0; y < snap.height; ++y)
      for (int x = 0; x < snap.width; ++x) {
        const Vec3d m = film_->mean(x, y);
        float* p = &snap.rgb[(size_t(y) * size_t(snap.width) + size_t(x)) * 3];
        p[0] = float(m.x), p[1] = float(m.y), p[2] = float(m.z);
      }
    snap.hasRecords = integrator->hasRecords();
    if (snap.hasRecords) snap.records = integrator->records();
    publish(std::move(snap));
  }
}

}  // namespace firstshot
