#pragma once
/// @file sample_shot.h
/// One light sample's share of the first-shot table: its window placed and rendered (or, in a
/// refinement pass, only the pixels around a few patches traced), and each patch's factor from the
/// analytic estimator (closed form × visible fraction) or the pixel sums. preprocess/preprocessor.cpp
/// runs these over all samples and assembles the table.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/lights/emission_profile.h"
#include "common/patches/patches.h"
#include "common/table/firstshot.h"
#include "common/util/math.h"
#include "preprocess/coverage.h"
#include "preprocess/exposure.h"
#include "preprocess/item_buffer.h"
#include "preprocess/kept_item_buffers.h"
#include "preprocess/occlusion_cull.h"
#include "preprocess/window.h"

namespace firstshot {

class GLReduce;

/// How one light sample is rendered: which window, where, and the scale from Σ weights to r_ij·A_j.
struct SampleSetup {
  const LightSample* sample = nullptr;
  const Window* window = nullptr;
  const std::vector<std::vector<double>>* weights = nullptr;  ///< the window's, or a spot's profiled copy
  Vec3d position{0.0};
  Vec3d axis{0, 0, 1};
  double rotation = 0;  ///< radians about the axis (settings.rotationSeed)
  double eyeOffset = 0;
  double scale = 1;
  EmissionProfile profile;  ///< a spot's profile (cone or IES table), for its numerical U_ij (common/lights/spot_integral.h)
  LightSampleKind kind = LightSampleKind::Point;
  bool analytic = true;  ///< closed form × visible fraction (preprocess/coverage.h)
};

/// One factor before it is sorted into the CSR table.
struct Entry {
  uint32_t patch;
  float factor;
  float visible;  ///< V_ij, the visible fraction (the refinement's measure); −1 if not computed
};

/// What one task of a shooting pass computes: a sample's factors over all patches, or over a
/// sorted subset of them (the children of patches split since the sample was last shot).
struct Task {
  uint32_t sample = 0;
  std::vector<uint32_t> patches;  ///< empty: all
};

/// r_ij of a patch with visible fraction @p fraction > 0 (closed-form kinds): the closed form times the
/// fraction, computed as the .fsd reader recomputes grouped factors (0 if the patch gets nothing).
float analyticPatchFactor(const SampleSetup& s, const Patch& p, double fraction);

/// A worker's scratch space for renderSample(), reused from one light sample to the next.
struct ShotScratch {
  std::vector<double> acc;                     ///< Σ weights per patch (all zero between calls)
  std::vector<uint32_t> touched;               ///< patches with acc > 0
  std::vector<std::vector<uint32_t>> ids;      ///< item buffer per view
  std::vector<uint32_t> candidates;            ///< patches the occlusion cull leaves
  std::vector<uint8_t> inTask;                 ///< per patch: in the task (all zero between calls)
  // ---- GPU reduction (preprocess/gl/gl_reduce.h) ----
  std::string glReduce = "cpu";                ///< cpu | gpu | auto (PreprocessOptions::glReduce)
  std::shared_ptr<GLReduce> gpu;               ///< the GL renderer's reducer, made on first use
  std::vector<PatchCoverage> coverage;         ///< from the GPU: per touched patch (sorted)
};

/// The first pass's item buffers kept for the refinement passes (preprocess/kept_item_buffers.h).
struct Keeping {
  KeptItemBuffers* buffers = nullptr;            ///< this sample's; null: none kept or used
  size_t maxBytes = 0;                           ///< first pass: keep them if they take at most this
  const std::vector<uint32_t>* first = nullptr;  ///< refinement pass: the split before it (AdaptiveMesh::split)
  int level = 0;                                 ///< refinement pass: its level (1, 2, …)
};

/// Renders one sample's views and returns its non-zero factors over @p task's patches, sorted by
/// patch. With @p needVisible, factors from pixel sums (spots, the pixels estimator) also get their
/// visible fraction. A task over all patches renders whole views with @p renderer (and keeps them
/// in @p keeping.buffers if asked). A task over a subset of patches (a refinement pass: the
/// children of a few split patches) reads the kept buffers brought up to the split, or if there
/// are none traces the pixels around those patches with @p exposure's ray caster.
std::vector<Entry> renderSample(ItemBufferRenderer* renderer, const SampleSetup& s, const PatchMesh& mesh, const Task& task,
                                bool needVisible, ShotScratch& scratch, ExposureCache* exposure,
                                const OcclusionCull* cull, const Keeping& keeping);

}  // namespace firstshot
