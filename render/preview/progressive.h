#pragma once
/// @file progressive.h
/// The preview's background renderer (no OpenGL): one worker thread renders passes of one sample
/// per pixel into a Film — pass k takes sample index k with the renderer's seeding, so after n
/// passes the film equals an offline render with n spp, bit for bit. After each pass it publishes
/// the mean image; a new job (camera, integrator, scene) cancels the pass in flight and restarts
/// the accumulation.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/scene/scene_desc.h"
#include "render/integrators/integrator.h"
#include "render/output/film.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// Makes a configured integrator by name (preprocess() is left to the caller).
using IntegratorFactory = std::function<std::unique_ptr<Integrator>(const std::string& name)>;

/// What to render. Changing any field restarts the accumulation.
struct ProgressiveJob {
  const RenderScene* scene = nullptr;  ///< must stay alive while the job may run
  std::string integrator = "path";
  CameraDesc camera;
};

/// The latest published state.
struct ProgressiveSnapshot {
  uint64_t generation = 0;     ///< the job it belongs to (see ProgressiveRenderer::submit)
  int spp = 0;                 ///< samples per pixel in the image
  double seconds = 0;          ///< render time of the job so far
  uint64_t rays = 0;           ///< rays traced by the job so far
  std::vector<float> rgb;      ///< mean radiance, width·height·3, top row first
  int width = 0, height = 0;
  bool hasRecords = false;     ///< the integrator keeps records
  std::vector<IntegratorRecord> records;  ///< its records after the last pass (when hasRecords)
  std::string error;           ///< non-empty if the job failed (e.g. integrator preprocess threw)
};

class ProgressiveRenderer {
 public:
  /// @param factory makes the job's integrator; called on the worker thread when the job's
  ///        integrator name or scene changes (the integrator is kept across camera changes)
  /// @param maxSpp passes per job, after which the worker waits for a new job
  /// @param sampler how the passes' samplers draw (RenderOptions::sampler)
  ProgressiveRenderer(IntegratorFactory factory, uint64_t seed, int threads, int maxSpp,
                      SamplerMode sampler = SamplerMode::Independent);
  ~ProgressiveRenderer();
  ProgressiveRenderer(const ProgressiveRenderer&) = delete;
  ProgressiveRenderer& operator=(const ProgressiveRenderer&) = delete;

  /// Starts a new job (cancelling the running pass); returns its generation number (1, 2, ...).
  uint64_t submit(const ProgressiveJob& job);
  /// Copies the latest snapshot into @p out if it is newer than @p out.generation / @p out.spp.
  /// @return true if @p out changed.
  bool poll(ProgressiveSnapshot& out) const;
  /// Blocks until the current job has @p spp samples per pixel (or has failed / is cancelled).
  void waitFor(int spp) const;
  /// A copy of the latest job's film (taken between passes), its spp and its generation.
  Film film(int& spp, uint64_t& generation) const;
  int maxSpp() const { return maxSpp_; }

 private:
  void run();

  IntegratorFactory factory_;
  uint64_t seed_;
  int threads_, maxSpp_;
  SamplerMode sampler_;

  mutable std::mutex mutex_;
  mutable std::condition_variable wake_;  ///< worker: a new job or stop; waiters: a pass finished
  ProgressiveJob job_;
  uint64_t generation_ = 0;
  bool stop_ = false;
  std::atomic<bool> cancel_{false};

  // Owned by the worker; read by film() under filmMutex_.
  mutable std::mutex filmMutex_;
  std::unique_ptr<Film> film_;
  int filmSpp_ = 0;
  uint64_t filmGeneration_ = 0;

  ProgressiveSnapshot published_;  ///< guarded by mutex_
  std::thread worker_;
};

}  // namespace firstshot
