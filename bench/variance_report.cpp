// Where a path-traced image's variance comes from (variance_report.h).
#include "bench/variance_report.h"

#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

#include "render/scene/embree_scene.h"

namespace firstshot {

namespace {

constexpr int kTerms = int(PathTerm::Count);
constexpr int kVias = int(PathVia::Count);

/// The categories' places in one flat array: (bounces, term, via), then (term, via), then bounces, then L.
struct Layout {
  int lengths;  ///< maxBounces + 1: 0 … maxBounces−1 and "maxBounces or more"
  int fine() const { return lengths * kTerms * kVias; }
  int termBase() const { return fine(); }
  int bouncesBase() const { return termBase() + kTerms * kVias; }
  int imageIndex() const { return bouncesBase() + lengths; }
  int size() const { return imageIndex() + 1; }
  int fineIndex(int b, int t, int v) const { return (std::min(b, lengths - 1) * kTerms + t) * kVias + v; }
  /// The category of flat index @p i, for the report.
  VarianceCategory category(int i) const {
    VarianceCategory c;
    if (i < fine()) c.bounces = i / (kTerms * kVias), c.term = i / kVias % kTerms, c.via = i % kVias;
    else if (i < bouncesBase()) c.term = (i - termBase()) / kVias, c.via = (i - termBase()) % kVias;
    else if (i < imageIndex()) c.bounces = i - bouncesBase();
    return c;
  }
};

/// One camera sample's amounts by fine category (values: the mean of the three channels) and their colour sum.
class SampleRecorder final : public PathRecorder {
 public:
  explicit SampleRecorder(const Layout& layout) : layout_(layout), x_(size_t(layout.fine()), 0.0) {}
  void record(int bounces, PathTerm term, PathVia via, const Color& value) override {
    total_ += value;
    const double v = (double(value.x) + double(value.y) + double(value.z)) / 3.0;
    if (v == 0.0) return;
    const int i = layout_.fineIndex(bounces, int(term), int(via));
    if (x_[size_t(i)] == 0.0) touched_.push_back(i);
    x_[size_t(i)] += v;
  }
  void clear() {
    for (int i : touched_) x_[size_t(i)] = 0.0;
    touched_.clear();
    total_ = Color(0.0f);
  }
  const std::vector<int>& touched() const { return touched_; }
  double value(int i) const { return x_[size_t(i)]; }
  const Color& total() const { return total_; }

 private:
  const Layout& layout_;
  std::vector<double> x_;
  std::vector<int> touched_;
  Color total_{0.0f};
};

/// Sums of one row of pixels, per flat category: Σ mean, Σ variance, max, non-zero count.
struct RowSums {
  std::vector<VarianceCategory> c;
  double partitionError = 0;
  uint64_t nonFinite = 0, rays = 0;
};

/// Row @p y: every pixel's samples, in the renderer's order (variance_report.h).
void renderRow(const Integrator& path, const Camera& camera, const Layout& layout, const VarianceReportOptions& o,
               int y, RowSums& row) {
  const int n = layout.size();
  row.c.assign(size_t(n), VarianceCategory());
  std::vector<double> s(static_cast<size_t>(n)), s2(static_cast<size_t>(n)), x(static_cast<size_t>(n), 0.0);
  std::vector<int> touched;
  SampleRecorder recorder(layout);
  PathRecorder*& slot = threadPathRecorder();
  for (int px = 0; px < camera.width(); ++px) {
    std::fill(s.begin(), s.end(), 0.0);
    std::fill(s2.begin(), s2.end(), 0.0);
    for (int k = 0; k < o.spp; ++k) {
      Sampler sampler = Sampler::make(o.sampler, o.seed, uint64_t(y) * uint64_t(camera.width()) + uint64_t(px),
                                      uint64_t(k));
      const Vec2 jitter = sampler.next2D();
      const Ray ray = camera.generateRay(float(px) + jitter.x, float(y) + jitter.y);
      recorder.clear();
      SampleInfo info;
      slot = &recorder;
      const Color L = path.Li(ray, sampler, &info);
      slot = nullptr;
      row.rays += info.rays;
      if (!isFinite(L)) {  // the renderer counts it as 0; so does every category
        ++row.nonFinite;
        continue;
      }
      const float scale = maxComponent(glm::abs(L));
      if (scale > 0.0f)
        row.partitionError = std::max(row.partitionError,
                                      double(maxComponent(glm::abs(recorder.total() - L))) / double(scale));
      // The sample's values: its fine categories, their sums by (term, via) and by length, and L.
      touched.clear();
      auto add = [&](int i, double v) {
        if (x[size_t(i)] == 0.0) touched.push_back(i);
        x[size_t(i)] += v;
      };
      for (int i : recorder.touched()) {
        const double v = recorder.value(i);
        const VarianceCategory c = layout.category(i);
        add(i, v);
        add(layout.termBase() + c.term * kVias + c.via, v);
        add(layout.bouncesBase() + c.bounces, v);
      }
      add(layout.imageIndex(), (double(L.x) + double(L.y) + double(L.z)) / 3.0);
      for (int i : touched) {
        const double v = x[size_t(i)];
        x[size_t(i)] = 0.0;
        if (v == 0.0) continue;
        s[size_t(i)] += v, s2[size_t(i)] += v * v;
        VarianceCategory& c = row.c[size_t(i)];
        c.maxSample = std::max(c.maxSample, v);
        ++c.nonZero;
      }
    }
    const double m = double(o.spp);
    for (int i = 0; i < n; ++i) {
      if (s2[size_t(i)] == 0.0) continue;
      row.c[size_t(i)].meanSum += s[size_t(i)] / m;
      row.c[size_t(i)].varianceSum += std::max(0.0, (s2[size_t(i)] - s[size_t(i)] * s[size_t(i)] / m) / (m - 1.0));
    }
  }
}

bool byVariance(const VarianceCategory& a, const VarianceCategory& b) { return a.varianceSum > b.varianceSum; }

}  // namespace

std::string VarianceCategory::name(int maxBounces) const {
  std::string s;
  if (bounces >= 0) s = bounces >= maxBounces ? fmt::format("{}+", maxBounces) : fmt::format("{}", bounces);
  if (term >= 0) s += (s.empty() ? "" : " ") + std::string(pathTermName(PathTerm(term)));
  if (via >= 0) s += (s.empty() ? "" : " ") + std::string(pathViaName(PathVia(via)));
  return s.empty() ? "L" : s;
}

double VarianceReport::relativeError() const {
  const double pixels = double(width) * double(height), mean = imageMean();
  return mean > 0.0 ? std::sqrt(image.varianceSum / pixels / double(spp)) / mean : 0.0;
}

VarianceReport varianceReport(const Integrator& path, const RenderScene& scene, const VarianceReportOptions& options) {
  VarianceReportOptions o = options;
  o.spp = std::max(2, o.spp);
  o.maxBounces = std::max(1, o.maxBounces);
  const Camera camera(scene.desc().camera);
  const Layout layout{o.maxBounces + 1};
  std::vector<RowSums> rows(size_t(camera.height()));
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpuStart = std::clock();
  tbb::task_arena arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, camera.height(), 1), [&](const tbb::blocked_range<int>& r) {
      enableFlushToZero();  // as the renderer's threads: the same arithmetic, the same image
      for (int y = r.begin(); y < r.end(); ++y) renderRow(path, camera, layout, o, y, rows[size_t(y)]);
    });
  });
  VarianceReport report;
  report.width = camera.width(), report.height = camera.height(), report.spp = o.spp, report.maxBounces = o.maxBounces;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.cpuSeconds = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;
  std::vector<VarianceCategory> total(size_t(layout.size()));
  for (int i = 0; i < layout.size(); ++i) total[size_t(i)] = layout.category(i);
  for (const RowSums& row : rows) {  // in row order: the same sums for any number of threads
    for (int i = 0; i < layout.size(); ++i) {
      VarianceCategory& t = total[size_t(i)];
      const VarianceCategory& c = row.c[size_t(i)];
      t.meanSum += c.meanSum, t.varianceSum += c.varianceSum, t.nonZero += c.nonZero;
      t.maxSample = std::max(t.maxSample, c.maxSample);
    }
    report.partitionError = std::max(report.partitionError, row.partitionError);
    report.nonFinite += row.nonFinite, report.rays += row.rays;
  }
  for (int i = 0; i < layout.size(); ++i) {
    const VarianceCategory& t = total[size_t(i)];
    if (i == layout.imageIndex()) report.image = t;
    else if (t.nonZero == 0) continue;
    else if (i < layout.fine()) report.categories.push_back(t), report.categoryVarianceSum += t.varianceSum;
    else if (i < layout.bouncesBase()) report.byTerm.push_back(t);
    else report.byBounces.push_back(t);
  }
  std::stable_sort(report.categories.begin(), report.categories.end(), byVariance);
  std::stable_sort(report.byTerm.begin(), report.byTerm.end(), byVariance);
  return report;
}

std::string formatVarianceReport(const VarianceReport& r, int top) {
  const double pixels = double(r.width) * double(r.height), mean = r.imageMean();
  const double var = r.image.varianceSum > 0.0 ? r.image.varianceSum : 1.0;
  std::string out = fmt::format(
      "{}x{} at {} spp: image mean {:.6g} W/(m² sr), relative RMS error {:.4f} (per-sample variance {:.4g} per "
      "pixel); the categories' variances add up to {:.1f}% of the image's (the rest: covariances); partition error "
      "{:.1e}; {} non-finite samples; {:.1f} M rays in {:.1f} s ({:.1f} CPU s)\n",
      r.width, r.height, r.spp, mean, r.relativeError(), r.image.varianceSum / pixels,
      100.0 * r.categoryVarianceSum / var, r.partitionError, r.nonFinite, double(r.rays) * 1e-6, r.seconds, r.cpuSeconds);
  auto table = [&](const char* title, const std::vector<VarianceCategory>& cats, size_t count) {
    out += fmt::format("\n{}\n| category | mean share | variance share | max sample / image mean | non-zero samples |\n"
                       "|---|---|---|---|---|\n", title);
    const double samples = pixels * double(r.spp), meanSum = r.image.meanSum != 0.0 ? r.image.meanSum : 1.0;
    for (size_t k = 0; k < std::min(count, cats.size()); ++k) {
      const VarianceCategory& c = cats[k];
      out += fmt::format("| {} | {:.4f} | {:.4f} | {:.3g} | {:.2e} |\n", c.name(r.maxBounces), c.meanSum / meanSum,
                         c.varianceSum / var, mean > 0.0 ? c.maxSample / mean : 0.0, double(c.nonZero) / samples);
    }
  };
  table("By (bounces, term, path), the largest variance shares first:", r.categories, size_t(std::max(0, top)));
  table("By (term, path), over every length:", r.byTerm, r.byTerm.size());
  table("By length in bounces:", r.byBounces, r.byBounces.size());
  return out;
}

std::string varianceReportCsv(const VarianceReport& r) {
  const double pixels = double(r.width) * double(r.height), mean = r.imageMean();
  const double var = r.image.varianceSum > 0.0 ? r.image.varianceSum : 1.0;
  const double meanSum = r.image.meanSum != 0.0 ? r.image.meanSum : 1.0;
  std::string out = "group,bounces,term,via,mean,mean_share,variance_share,max_sample_over_image_mean,nonzero_fraction\n";
  auto rows = [&](const char* group, const std::vector<VarianceCategory>& cats) {
    for (const VarianceCategory& c : cats)
      out += fmt::format("{},{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", group,
                         c.bounces < 0 ? "" : c.bounces >= r.maxBounces ? fmt::format("{}+", r.maxBounces)
                                                                        : fmt::format("{}", c.bounces),
                         c.term < 0 ? "" : pathTermName(PathTerm(c.term)), c.via < 0 ? "" : pathViaName(PathVia(c.via)),
                         c.meanSum / pixels, c.meanSum / meanSum, c.varianceSum / var,
                         mean > 0.0 ? c.maxSample / mean : 0.0, double(c.nonZero) / (pixels * double(r.spp)));
  };
  rows("image", {r.image});
  rows("category", r.categories);
  rows("term", r.byTerm);
  rows("bounces", r.byBounces);
  return out;
}

}  // namespace firstshot
