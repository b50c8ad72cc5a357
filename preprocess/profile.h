#pragma once
/// @file profile.h
/// Where firstshot-preprocess spends its time (docs/preprocess-performance.md). With the environment
/// variable FIRSTSHOT_PROFILE set (to anything but 0), phases add the thread time spent in them to
/// process-wide counters and preprocessScene()/main print the table to stderr; otherwise a Scope costs
/// one branch. Counters are thread-seconds summed over workers (so they add up to about user time),
/// not wall time.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>

namespace firstshot::profile {

enum Phase : int {
  Windows,         ///< window geometry and weight tables
  Mesh,            ///< patches (adaptive mesh) and item geometry
  RendererSetup,   ///< GL context + vertex buffers, or the Embree BVH of a worker's renderer
  ProbeSetup,      ///< the Embree BVH the exact point tests and exposure probes share
  Render,          ///< item buffer: GL draw (to glFinish) or Embree rays
  Readback,        ///< GL glReadPixels
  Accumulate,      ///< Σ weights per patch
  GpuReduce,       ///< GL back end reducing on the GPU: touched sums (dispatch, gather, read-back)
  GpuJobs,         ///< the same: the coverage jobs set up on the CPU (projections, pixel boxes, tiles)
  GpuCoverage,     ///< the same: coverage sums (upload of the jobs, dispatches, read-back)
  Kept,            ///< item buffers kept for the refinement passes: runs, splits followed, unpacked
  Coverage,        ///< analytic estimator: patchCoverage (software rasterisation + exact tests)
  CoverageExposed, ///< the same again over the exposed part of partly buried patches
  PointTests,      ///< analytic estimator: point tests of small or unseen patches
  Exposure,        ///< buried-part probes (ExposureCache masks)
  Integral,        ///< closed-form integrals and emitting entries
  Table,           ///< CSR table assembly
  Write,           ///< .fsd file write
  Count
};

inline const char* name(Phase p) {
  static const char* names[] = {"windows", "mesh", "renderer setup (GL context / Embree BVH)", "probe BVH",
                                "render (draw / rays)", "readback", "accumulate",
                                "GPU reduction: touched sums", "GPU reduction: job set-up (CPU)",
                                "GPU reduction: coverage sums", "kept item buffers", "coverage (patchCoverage)",
                                "coverage of exposed parts",
                                "point tests", "exposure probes", "closed forms + entries", "table assembly",
                                "file write"};
  return names[p];
}

bool enabled();
void add(Phase p, int64_t nanoseconds);
int64_t total(Phase p);
/// Prints the counters (thread-seconds and share) to @p out.
void report(std::FILE* out);

/// Adds the time from construction to destruction (or stop()) to phase @p p, when profiling.
class Scope {
 public:
  explicit Scope(Phase p) : p_(p), on_(enabled()) {
    if (on_) t0_ = std::chrono::steady_clock::now();
  }
  ~Scope() { stop(); }
  void stop() {
    if (!on_) return;
    on_ = false;
    add(p_, std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0_).count());
  }
  Scope(const Scope&) = delete;
  Scope& operator=(const Scope&) = delete;

 private:
  Phase p_;
  bool on_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace firstshot::profile
