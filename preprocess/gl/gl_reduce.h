#pragma once
/// @file gl_reduce.h
/// Item buffers reduced on the GPU: with the GL back end, a light sample's views are rendered
/// into R32UI textures that stay in GPU memory (GLItemBuffer::renderToTexture) and compute shaders (GL 4.3)
/// produce, per patch, what renderSample() otherwise computes on the CPU from the read-back buffers:
///  - the touched sum Σ w over the pixels showing the patch (and the list of touched patches), and
///  - the analytic estimator's coverage sums of every touched patch (patchCoverage() without exposure:
///    expected, visible, pixels), with the same pixel centres, the same 3×3 occluder proposals and the
///    same exact ray test in double precision (GLSL `precise` doubles, the CPU's expressions in its order).
/// Only these per-patch sums are read back. The patches' clipped projections and pixel boxes are set up
/// on the CPU (coverageSetup(), the CPU's own code), the per-pixel work runs on the GPU: one work group of
/// 256 per tile of 256 pixels of a (touched patch, view)'s box.
///
/// Determinism: the window weights are uploaded once per window as 64-bit fixed-point integers
/// (w · 2^k rounded down, at least 1 where w > 0, k such that the window's total stays below 2^61) and
/// summed with integer additions (32-bit atomics carrying into the high word, work-group sums in shared
/// memory): integer sums do not depend on the order, so the table is the same on every run. Against the
/// CPU's double sums they differ by the quantisation, ≤ 2^-k per pixel (about 1e-18 of the window's total
/// at R = 512): the same table within float rounding.
///
/// What stays on the CPU, exactly as without it: the buried-part re-test of partly visible patches
/// (exposure masks; the item buffers are then read back for that sample), the kept item buffers of the
/// refinement passes (read back when kept), the point tests of patches with too few pixel centres
/// (Embree rays), the refinement passes' masked item buffers (Embree), and cut-out scenes (their GL item buffers
/// discard the holes, but the coverage of a cut-out patch needs its alpha per pixel centre: reduced on the CPU).
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/patches/patches.h"
#include "preprocess/coverage.h"
#include "preprocess/view.h"

namespace firstshot {

class GLItemBuffer;
class ItemBufferRenderer;

/// "cpu" | "gpu" | "auto"; @throws std::invalid_argument otherwise.
void checkGLReduceMode(const std::string& mode);

class GLReduce {
 public:
  /// The reducer of @p renderer when its item buffers are reduced on the GPU: @p mode "gpu", or "auto" on a
  /// renderer that is not a software rasteriser; null for "cpu", a non-GL renderer, or "auto" on llvmpipe.
  /// @p cache holds the reducer between samples (made on first use over @p mesh).
  static GLReduce* forRenderer(ItemBufferRenderer* renderer, const PatchMesh& mesh, const std::string& mode,
                               std::shared_ptr<GLReduce>& cache);

  /// Compiles the compute shaders and uploads @p mesh's patches (double vertices and planes) once.
  /// @throws std::runtime_error if the context lacks compute shaders or a shader fails to compile
  GLReduce(GLItemBuffer& gl, const PatchMesh& mesh);
  ~GLReduce();
  GLReduce(const GLReduce&) = delete;
  GLReduce& operator=(const GLReduce&) = delete;

  /// Renders @p views into textures and returns the touched patches (any order) and their Σ w added to
  /// @p acc (per patch, zero on entry for them). @p weights: per view, the window's weight per pixel.
  void touch(const std::vector<View>& views, const std::vector<std::vector<double>>& weights,
             std::vector<uint32_t>& touched, std::vector<double>& acc);
  /// Coverage sums (patchCoverage() summed over the views, no exposure) of every patch of @p touched, in its
  /// order, over the item buffers of the last touch().
  void coverage(const std::vector<View>& views, const std::vector<uint32_t>& touched, double near,
                std::vector<PatchCoverage>& out);
  /// The item buffers of the last touch(), read back (one per view).
  void readBack(std::vector<std::vector<uint32_t>>& ids);

 private:
  struct WindowWeights {
    unsigned int buffer = 0;
    int shift = 0;                 ///< k: fixed point = w · 2^k
    std::vector<uint32_t> offset;  ///< per view, its first pixel in the buffer
  };
  const WindowWeights& weightsFor(const std::vector<std::vector<double>>& weights);

  GLItemBuffer& gl_;
  uint32_t patchCount_ = 0;
  std::vector<Patch> patches_;  ///< the mesh's patches (coverageSetup on the CPU)
  unsigned int touchProgram_ = 0, gatherProgram_ = 0, coverageProgram_ = 0;
  unsigned int patchBuffer_ = 0, accBuffer_ = 0, flagBuffer_ = 0, listBuffer_ = 0, outBuffer_ = 0;
  unsigned int jobDBuffer_ = 0, jobIBuffer_ = 0, tileBuffer_ = 0, sumBuffer_ = 0;
  std::map<const void*, WindowWeights> windows_;  ///< by the weights' address (they live for the whole run)
  const WindowWeights* current_ = nullptr;        ///< of the last touch()
  size_t views_ = 0;                              ///< of the last touch()
  std::vector<unsigned int> textures_;            ///< its item buffers, one per view
};

}  // namespace firstshot
