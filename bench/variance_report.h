#pragma once
/// @file variance_report.h
/// Where a path-traced image's variance comes from: each camera sample of the path tracer (the `path` integrator's
/// own walk, render/integrators/common/path_walk.h) traced with a recorder (path_recorder.h) that keeps every
/// amount added to the sample's radiance apart by category, (bounces, term, via): the path length at which it
/// arrives, what brought it (an emitter met, NEE, the first-shot term, patch NEE, …) and whether it passed a glossy
/// or a delta vertex. Per pixel each category's samples give its mean and its per-sample variance; the report sums
/// them over the pixels. The categories partition each sample's radiance, so their means add up to the image's;
/// their variances add up to the image's only without covariances, and the report gives both.
///
/// A value is the mean of a colour's three channels, W/(m² sr). The renderer's sample order is kept (the same
/// sampler per pixel and sample index, the same camera ray), so the image is the one `firstshot-render
/// --integrator path` makes with the same options and seed (up to the order of float additions in the sums).
#include <cstdint>
#include <string>
#include <vector>

#include "common/sampling/rng.h"
#include "render/integrators/common/path_recorder.h"
#include "render/integrators/integrator.h"
#include "render/scene/camera.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// How the report renders.
struct VarianceReportOptions {
  int spp = 16;             ///< camera samples per pixel (≥ 2: a variance needs two)
  uint64_t seed = 1;        ///< the renderer's seed (RenderOptions::seed)
  SamplerMode sampler = SamplerMode::Independent;
  int threads = 0;          ///< 0: as many as TBB likes; the report does not depend on it
  int maxBounces = 8;       ///< bounce counts from this one on share a category ("8+")
};

/// One category's figures, summed over the image's pixels.
struct VarianceCategory {
  int bounces = -1;  ///< path length in bounces (PathRecorder::record); −1 in a total over every length
  int term = -1;     ///< PathTerm, −1 in a total over every term
  int via = -1;      ///< PathVia, −1 in a total over every kind of path
  double meanSum = 0;      ///< Σ over pixels of the category's mean per sample
  double varianceSum = 0;  ///< Σ over pixels of the category's per-sample variance (unbiased, n − 1)
  double maxSample = 0;    ///< the largest single-sample value of the category anywhere
  uint64_t nonZero = 0;    ///< samples in which the category added something
  /// "2 patch-nee glossy", "patch-nee", "bounces 3", "8+ …".
  std::string name(int maxBounces) const;
};

/// The report of one render.
struct VarianceReport {
  int width = 0, height = 0, spp = 0, maxBounces = 8;
  VarianceCategory image;                    ///< the sample's whole radiance L
  std::vector<VarianceCategory> categories;  ///< (bounces, term, via), those that ever added something
  std::vector<VarianceCategory> byTerm;      ///< (term, via) over every length
  std::vector<VarianceCategory> byBounces;   ///< by length over every term
  double categoryVarianceSum = 0;  ///< Σ over the categories of varianceSum (image.varianceSum less the covariances)
  /// The largest |Σ categories − L| of one sample, relative to max(|L|, 1e-6 × the image mean): float rounding.
  double partitionError = 0;
  uint64_t nonFinite = 0;  ///< samples whose L was not finite: counted as 0 in every category, as the renderer does
  uint64_t rays = 0;
  double seconds = 0;     ///< wall time of the render, s
  double cpuSeconds = 0;  ///< CPU time of the render, all threads, s (steadier than wall time on a shared machine)

  double imageMean() const { return image.meanSum / (double(width) * double(height)); }
  /// RMS over pixels of the pixel estimate's standard error at spp samples, relative to the image mean.
  double relativeError() const;
};

/// Renders @p scene's camera view with @p path, the `path` integrator already preprocessed for @p scene, and splits
/// every sample as the file comment says.
VarianceReport varianceReport(const Integrator& path, const RenderScene& scene, const VarianceReportOptions& options);

/// The report as a Markdown-ish text table: the totals, the top @p top categories by variance share, every
/// (term, via) and every length.
std::string formatVarianceReport(const VarianceReport& report, int top);

/// The report as CSV: one row per category and total (group, bounces, term, via, mean share, variance share, max
/// sample / image mean, fraction of samples non-zero).
std::string varianceReportCsv(const VarianceReport& report);

}  // namespace firstshot
