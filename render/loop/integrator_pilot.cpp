// --integrator auto's pilot: small pictures of the camera's view, each candidate's efficiency from its noise and
// its counted rays.
#include "render/loop/integrator_pilot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "render/loop/pilot_image.h"
#include "render/loop/pilot_records.h"
#include "render/loop/renderer.h"
#include "render/scene/camera.h"

namespace firstshot {

namespace {

/// Of kPilotShare, the share of the render's rays the plan gives the candidates' images; the rest is for what some take
/// beyond their images' rays (kMinPasses passes, the cache's four images and two fills, the probes): with all of it
/// planned the pilot took 4.0–6.3% of the render (median 4.9%) over 56 pilots.
constexpr double kPlannedShare = 0.04;
constexpr double kPilotClamp = 5.0;   ///< pixel values above this many image means count as that much (pilotNoise)
/// A relative error below this counts as this much: methods that exact (the direct light of a point over a plane by
/// next-event estimation: two pictures alike) are equals, the cheaper the better. Without it an error of 0 made an
/// efficiency of 0, and such scenes went to the noisiest method whose error was not quite 0.
constexpr double kMinError = 1e-4;
constexpr int kMaxSide = 48;          ///< the pilot picture's longer side at most, pixels
constexpr int kMinSide = 16;          ///< its shorter side at least, pixels
constexpr int kMinSpp = 4;            ///< samples per pixel of a pilot image at least
constexpr int kMinPasses = 2;         ///< passes of a candidate's pilot image at least
constexpr int kMaxPasses = 256;       ///< and at most
/// A light path of light tracing costs about this many of the path tracer's camera samples (its rays per path 1.2–3×
/// the path tracer's per sample on the shipped Cornell boxes and the many-lights room, a pass's camera sample on top):
/// the pilot takes at most PilotPlan::lightPaths = spp / (this × kMinPasses) light paths per pixel and pass.
constexpr int kLightPathCost = 2;
/// The path tracer's and the irradiance cache's rays with patch NEE count this much work each: sampling the lit
/// patches (their light tree, each patch's first-shot light) took 1.8–3.0× the time per ray of the same path tracer
/// without it (2.2–2.9× on six of seven scenes with their tables at 128 × 128; no ray count shows that work), and
/// the cache's fill 2.0× (McGuire's box with its table at 1024 rays per record: 1.17 against 2.3 Mrays/s; counted at
/// one, `--patch-nee every` took that fill, 23.5 s of a 20-s render).
constexpr double kPatchNeeRayCost = 2.5;
/// Where the pilot weighs reading a table against leaving it unread (the path tracer without it), the rays of a
/// method that reads it count this much work each: its lookups (a hit's first-shot light, shooting from the lit
/// patches) took more time per ray than the same method's without the table, the path tracer's 1.33× (median of 28
/// shipped and public scenes with their tables, 128 × 128; 0.53–2.39), light tracing's and BDPT's 1.43× and 1.46×
/// (bench/table_ray_cost.sh; 1.52×, 1.77× and 1.70× while a table's patches were traced, not its faces).
constexpr double kTableRayCost = 1.35;
/// BDPT's rays count this much work each: joining its subpaths evaluates two BSDFs and every strategy's MIS densities
/// per connection, work no ray count shows; its time per ray was 1.34 times the path tracer's and 1.17 times light
/// tracing's (medians over 24 shipped and public scenes without a table, bench/table_ray_cost.sh: 0.40–2.48 and
/// 1.01–1.90). Counted at one, the pilot took BDPT with veach-bidir's table for seed 1 (figure 1 against light
/// tracing's 0.959), where at 20 s it is 0.63 times light tracing's efficiency with the table.
constexpr double kBdptRayCost = 1.3;
/// The cache's records' error falls as (records' picture's pixels)^−this: an interpolation error that falls as the
/// records' spacing. 12 × 12 records against the render's own at 128 × 128 left 0.016 against at most 0.0051 in the
/// glass-bulb room, 0.029 against at most 0.010 in the bowl-lamp room: at least 0.24 and 0.22. With 0.23 and the
/// render's work at kTimeRaysRate, three Cornell boxes with their tables left the cache, which is 2.15–3.8× the
/// choices made instead there. Where the records' own noise dominates (daylight, the classroom) it falls more slowly;
/// the pilot does not tell the two apart.
constexpr double kRecordsErrorExponent = 0.5;
/// A seeded preprocessing's rays (the cache's fill: records gathered, their neighbours clamped) count this much work
/// each: over the 19 scenes where the cache is chosen they took 1.33–3.27× the time of the path tracer's rays
/// (median 1.88; 128 × 128, one thread; bench/cache_ray_cost.sh), where its passes' rays took 0.57–1.60× (median
/// 1.18, counted as one).
constexpr double kFillRayCost = 1.9;
/// A seeded preprocessing's rays grow as (its picture's pixels)^this: its records are placed by the surfaces' shape
/// and the light, and fewer are new as the pixels grow. Measured from 12 × 12 to 128 × 128 at 512 rays per record,
/// with their tables: the Cornell box 0.81, Bitterli's 0.81, McGuire's 0.87, the glass-bulb room 0.84, the bowl-lamp
/// room 0.83, the textured room 0.87, the daylit office 0.83 (median 0.83). In proportion to the pixels (as until
/// 2026-11-30) the bowl-lamp room's fill came out at 82–85% of the render's rays, about three times its own, and the
/// cache + table, 13× light tracing there, tied.
constexpr double kFillGrowth = 0.83;
/// The pilot's fills take this many times the seconds per ray of the render's fill: so grown, their time projected
/// the render's fill at 0.97-1.66 times its real time, median 1.24, over six scenes with their tables forced to the
/// cache at 20 s (2026-12-02, the 43rd session). PilotFigure::fillSeconds is divided by it.
constexpr double kPilotFillSlowdown = 1.25;
/// The render's records may take up to this many times the hemisphere rays the pilot's took (PilotFigure::recordSamples)
constexpr int kMaxRecordSamples = 16;
/// and only while their fill stays within kMaxRecordsFillShare of the render's work (a fill projected wrong by its
/// growth exponent still leaves the render time); where recordSamplesForTime finds this machine's fill past
/// kFillTimeShare of the render's seconds, it keeps it within kMaxFillShare of them. At 0.5 of the work Bitterli's
/// box with its table kept 512 rays per record (its fill projected to 29.8%, 25% of the time), where 1024 (48% of the
/// time) left 0.0073 against 0.0103 (docs/measurements.md).
constexpr double kMaxRecordsFillShare = 0.75;
constexpr double kMaxFillShare = 0.5;
/// The fewest hemisphere rays per record recordSamplesForTime takes, as a multiple of the pilot's (512 → 128).
constexpr double kLeastRecordSamples = 0.25;
/// A candidate whose kMinPasses passes would take more than this many times an image's rays is not tried (NEE to each
/// of the many-lights room's 64 lights: 20 times, the office floor's: 7; BDPT in the textured room: 2.2, tried); a
/// pass over the seeded preprocessing's smaller picture tells.
constexpr double kMaxMinPassesShare = 4.0;
/// A candidate whose images would take more than this many times their plan's rays (kMinPasses passes of a costly
/// pass) is not tried where they would leave the pilot too little of its kPilotShare for the plan of the candidates
/// after it; those within their plan are always tried, and so is a seeded preprocessing (the cache: its two fills at
/// the render's hemisphere rays per record are its measurement; at a half or a quarter of them its fill's growth was
/// projected short, docs/measurements.md).
constexpr double kOverPlan = 1.25;
constexpr int kFillDivisor = 4;       ///< a seeded preprocessing's picture: the pilot picture's sides divided by this
constexpr int kMinFillSide = 4;       ///< and at least this many pixels each

/// Work per ray of @p c's rays: kPatchNeeRayCost for the path tracer's and the irradiance cache's with patch NEE,
/// kBdptRayCost for BDPT's, times kTableRayCost for a method reading the table where others leave it unread
/// (@p weighTable); 1 for the others.
double rayCost(const PilotCandidate& c, bool weighTable) {
  const bool nee = (c.integrator == "path" || c.integrator == "irradiance-cache") && c.patchNee != PatchNee::Off;
  const double own = nee ? kPatchNeeRayCost : c.integrator == "bdpt" ? kBdptRayCost : 1.0;
  return own * (weighTable && c.table ? kTableRayCost : 1.0);
}

const char* patchNeeName(PatchNee p) { return p == PatchNee::Off ? "off" : p == PatchNee::First ? "first" : "every"; }

/// The picture of @p width × @p height scaled by @p f, each side at least 1.
void scaled(int width, int height, double f, int& w, int& h) {
  w = std::max(1, int(std::floor(width * f)));
  h = std::max(1, int(std::floor(height * f)));
}

}  // namespace

std::string PilotCandidate::label() const {
  std::string s = integrator;
  if (variesPatchNee) s += std::string(" --patch-nee ") + patchNeeName(patchNee);
  if (variesShoot) s += shootFromPatches ? " --shoot-firstshot patches" : " --shoot-firstshot off";
  if (everyLight) s += " --light-sampler all";
  if (!table) s += ", no table";
  return s;
}

PilotPlan planPilot(const CameraDesc& camera, int spp, size_t candidates, double seconds) {
  PilotPlan plan;
  if (candidates < 2 || spp < 1 || camera.width < 1 || camera.height < 1) return plan;
  const double pixels = double(camera.width) * double(camera.height);
  const double perImage = kPlannedShare * pixels * double(spp) / (2.0 * double(candidates));  // camera samples
  // The largest picture up to kMaxSide that still gets kMinSpp samples per pixel.
  double f = std::min(1.0, double(kMaxSide) / double(std::max(camera.width, camera.height)));
  f = std::min(f, std::sqrt(perImage / (kMinSpp * pixels)));
  int w = 0, h = 0;
  scaled(camera.width, camera.height, f, w, h);
  if (std::min(w, h) < std::min(kMinSide, std::min(camera.width, camera.height))) return plan;
  plan.width = w;
  plan.height = h;
  plan.spp = int(std::floor(perImage / (double(w) * double(h))));
  plan.lightPaths = std::max(1, plan.spp / (kLightPathCost * kMinPasses));
  plan.renderSpp = spp;
  plan.renderWork = seconds > 0.0 ? seconds * kTimeRaysRate : 0.0;
  plan.run = plan.spp >= kMinSpp;
  return plan;
}

CameraDesc pilotCamera(const CameraDesc& camera, const PilotPlan& plan) {
  CameraDesc c = camera;
  c.width = plan.width;
  c.height = plan.height;
  return c;
}

CameraDesc pilotFillCamera(const CameraDesc& camera, const PilotPlan& plan) {
  CameraDesc c = camera;
  c.width = std::max(std::min(kMinFillSide, plan.width), plan.width / kFillDivisor);
  c.height = std::max(std::min(kMinFillSide, plan.height), plan.height / kFillDivisor);
  return c;
}

namespace {

/// The mean of @p a and @p b over the pixels @p skip keeps (all without it); @p n: the values counted.
double keptMean(const std::vector<double>& a, const std::vector<double>& b, const std::vector<uint8_t>* skip,
                double& n) {
  double sum = 0.0;
  n = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (skip && (*skip)[i / 3]) continue;
    sum += a[i] + b[i];
    n += 1.0;
  }
  return n > 0.0 ? sum / (2.0 * n) : 0.0;
}

/// The pixels the figures count: those @p skip keeps, or every pixel (then clamped, pilotNoise) where those have no
/// light (nothing lit but the lamps and mirrors).
const std::vector<uint8_t>* countedPixels(const std::vector<double>& a, const std::vector<double>& b,
                                          const std::vector<uint8_t>* skip) {
  double n = 0.0;
  return skip && keptMean(a, b, skip, n) > 0.0 ? skip : nullptr;
}

}  // namespace

double pilotNoise(const std::vector<double>& a, const std::vector<double>& b, const std::vector<uint8_t>* skip,
                  bool clamp) {
  if (a.empty()) return 0.0;
  skip = countedPixels(a, b, skip);
  double n = 0.0;
  const double mean = keptMean(a, b, skip, n);
  if (!(mean > 0.0)) return 0.0;
  const double top = skip && !clamp ? std::numeric_limits<double>::infinity() : kPilotClamp * mean;
  double diff2 = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (skip && (*skip)[i / 3]) continue;
    const double d = std::min(a[i], top) - std::min(b[i], top);
    diff2 += d * d;
  }
  return std::sqrt(diff2 / (2.0 * n)) / mean;
}

std::vector<uint8_t> pixelsSeenAsTheyAre(const RenderScene& scene, const CameraDesc& desc) {
  const Camera camera(desc);
  std::vector<uint8_t> skip(size_t(desc.width) * size_t(desc.height), 0);
  constexpr int kMaxPanes = 8;
  for (int y = 0; y < desc.height; ++y)
    for (int x = 0; x < desc.width; ++x) {
      uint8_t& seen = skip[size_t(y) * size_t(desc.width) + size_t(x)];
      for (int k = 0; k < 4 && !seen; ++k) {
        Ray ray = camera.generateRay(float(x) + 0.25f + 0.5f * float(k % 2), float(y) + 0.25f + 0.5f * float(k / 2));
        Hit hit;
        for (int pane = 0; pane <= kMaxPanes && scene.intersect(ray, hit); ++pane) {
          const BSDF bsdf = scene.bsdfAt(hit);
          if (bsdf.thinGlass() && pane < kMaxPanes) {  // seen through
            ray.tmin = hit.t + hit.eps / glm::length(ray.d);
            continue;
          }
          seen = bsdf.hasDelta() || (!hit.onPatch() && maxComponent(scene.lights().emitted(hit, -ray.d)) > 0.0f);
          break;
        }
      }
    }
  return skip;
}

std::vector<PilotFigure> runPilot(const RenderScene& scene, const RenderScene* withoutTable,
                                  const std::vector<PilotCandidate>& candidates, const PilotPlan& plan,
                                  const PilotFactory& make, uint64_t seed, SamplerMode sampler, int threads,
                                  const std::function<void(size_t)>& progress) {
  const CameraDesc desc = pilotCamera(scene.desc().camera, plan), fillDesc = pilotFillCamera(scene.desc().camera, plan);
  const Camera camera(desc);
  const std::vector<uint8_t> skip = pixelsSeenAsTheyAre(scene, desc);
  // Every image gets the same rays (the budget): what the first candidate (the path tracer, unless the options given
  // left it out) traces in plan.spp passes and its preprocessing; a candidate of costlier samples takes fewer passes,
  // one of cheaper samples more. One candidate's integrators live at a time.
  double budget = 0.0, firstCost = 1.0;  // rays; the first candidate's work per ray (rayCost)
  // The render's work per pilot picture (G): its samples at the first candidate's work per sample (@p b, the budget
  // of plan.spp passes), or the time's rays; and a seeded preprocessing's picture against the pilot's.
  const double renderPixels = double(scene.desc().camera.width) * double(scene.desc().camera.height);
  auto renderWork = [&](double b) {
    return plan.renderWork > 0.0 ? plan.renderWork * double(desc.width) * double(desc.height) / renderPixels
                                 : b * firstCost * double(plan.renderSpp) / double(std::max(1, plan.spp));
  };
  const double fillScale =
      double(desc.width) * double(desc.height) / (double(fillDesc.width) * double(fillDesc.height));
  std::vector<PilotFigure> figures;
  // Integrators (and whether they read the table) whose preprocessing outgrew the pilot: their variants are skipped.
  std::vector<std::pair<std::string, bool>> outgrown;
  double spent = 0.0, share = 0.0;  // the pilot's rays so far, and at most (kPilotShare of the render's)
  // Passes of an image of @p pass rays a pass after @p preprocessing: imageBudget's rays, a seeded preprocessing's four
  // images (two fills) in the rays of two. imageBudget is the budget, or where a costly candidate before (the cache's
  // fills) left less of the pilot's share, an equal part of what is left for each candidate still to come (its
  // passes then rounded down).
  double imageBudget = 0.0;
  auto passesFor = [&](double preprocessing, double pass, bool seeded) {
    const double passes = (imageBudget - preprocessing) / (seeded ? 2.0 * pass : pass);
    return int(std::clamp<double>(imageBudget < budget ? std::floor(passes) : std::round(passes), double(kMinPasses),
                                  double(kMaxPasses)));
  };
  for (size_t c = 0; c < candidates.size(); ++c) {
    const std::pair<std::string, bool> kind{candidates[c].integrator, candidates[c].table};
    imageBudget = c == 0 ? budget : std::min(budget, (share - spent) / (2.0 * double(candidates.size() - c)));
    if (std::find(outgrown.begin(), outgrown.end(), kind) != outgrown.end()) {
      figures.emplace_back().skip = PilotSkip::Variant;
      if (progress) progress(c);
      continue;
    }
    if (!candidates[c].table && !withoutTable)
      throw std::logic_error("runPilot: a candidate without the table needs the scene without it");
    const RenderScene& theirs = candidates[c].table ? scene : *withoutTable;
    const std::unique_ptr<Integrator> integrator = make(candidates[c], seed);
    integrator->keyMissPaths(kPilotMissSalt);
    // Past the first candidate, whose rays set the budget: preprocessing (the cache's fill) stops past the first's
    // work in two images at the pilot's whole share (kPilotShare, not the plan's), or past what would take the whole
    // render once projected to it, whichever is more (at most a share of the render of 2 × its fill picture's pixels /
    // the render's, under 1% at 128 × 128): there it outgrows the pilot, and the candidate is not measured further.
    const double fillCost = rayCost(candidates[c], withoutTable != nullptr) * kFillRayCost;
    const bool seeded = integrator->seededPreprocess();
    double limit = std::max(kPilotShare / kPlannedShare * 2.0 * budget * firstCost,
                            renderWork(budget) / (fillScale * fillCost));
    // A seeded preprocessing is made twice (the cache's two fills): both must leave, of the pilot's share, its own
    // four images and two for each candidate after it at kMinPasses passes of the first candidate's.
    const double minImages = 2.0 * kMinPasses * budget / double(std::max(1, plan.spp));
    if (seeded) limit = std::min(limit, (share - spent - minImages * double(2 + candidates.size() - c - 1)) / 2.0);
    if (c > 0) integrator->limitPreprocessRays(uint64_t(std::max(0.0, limit)) + 1);
    const CameraDesc& preprocessDesc = seeded ? fillDesc : desc;
    integrator->preprocessFor(theirs, preprocessDesc);
    PilotFigure f;
    const double preprocessed = double(integrator->preprocessRayCount());
    if (c > 0 && preprocessed > limit) {
      f.rays = f.pilotRays = preprocessed;
      f.skip = PilotSkip::Outgrown;
      outgrown.push_back(kind);
    } else if (c > 0) {  // one pass over a picture of a sixteenth of the pixels: what a pass of its costs
      PilotImage probe(*integrator, fillDesc);
      probe.renderTo(1, Camera(fillDesc), seed, seed, seeded ? SamplerMode::Independent : sampler, threads);
      f.pilotRays = probe.firstPass;
      const double pass = std::max(1.0, probe.firstPass * fillScale);
      // What its two images would take (not a seeded preprocessing's: it is always tried).
      const double images = seeded ? 0.0 : 2.0 * (preprocessed + passesFor(preprocessed, pass, false) * pass);
      if (kMinPasses * pass > kMaxMinPassesShare * budget) {
        f.rays = pass;  // its two passes would take the others' rays many times over
        f.skip = PilotSkip::PassCost;
      } else if (images > kOverPlan * 2.0 * budget &&
                 spent + f.pilotRays + images + 2.0 * budget * double(candidates.size() - c - 1) > share) {
        f.rays = images / 2.0;  // more than its plan, and it would leave the candidates after it less than theirs
        f.skip = PilotSkip::Share;
      }
      if (f.skip != PilotSkip::None) f.pilotRays += preprocessed;
    }
    if (f.skip == PilotSkip::None) {
      // A seeded preprocessing's passes take independent samples: the films' per-pixel variances / samples are then
      // the passes' noise, which splits off the records' (with the render's stratified samples they overstate it, and
      // the records' part came out 0 nearly everywhere); the passes' noise so measured errs against the cache.
      const SamplerMode passSampler = seeded ? SamplerMode::Independent : sampler;
      PilotImage first(*integrator, desc);
      first.renderTo(1, camera, seed, seed, passSampler, threads);
      const double cost = rayCost(candidates[c], withoutTable != nullptr);
      const double pass = std::max(1.0, first.firstPass), preprocessing = first.rays - first.firstPass;
      if (c == 0) {
        budget = imageBudget = double(plan.spp) * pass + preprocessing;
        firstCost = cost;
        share = kPilotShare * pass * double(plan.renderSpp) * renderPixels / (double(desc.width) * double(desc.height));
      }
      f.spp = passesFor(preprocessing, pass, seeded);  // two images of equal rays each
      first.renderTo(f.spp, camera, seed, seed, passSampler, threads);
      // The second seed's image: a fresh integrator only where its preprocessing drew on the seed (the cache's
      // fill); the others render it with the first's (the same preprocessing, counted for both images).
      std::unique_ptr<Integrator> other;
      if (seeded) {
        other = make(candidates[c], seed + 1);
        other->keyMissPaths(kPilotMissSalt);
        other->preprocessFor(theirs, preprocessDesc);
        f.fillSeconds = (integrator->preprocessSeconds() + other->preprocessSeconds()) / 2.0;
      }
      PilotImage second(other ? *other : *integrator, desc);
      // The second image's camera samples at the first's positions in their pixels: the edges' aliasing, which the
      // render's stratified samples nearly remove as they add up, would otherwise be most of the pilot's noise
      // where the light is smooth, and hide what a method gains there.
      second.renderTo(f.spp, camera, seed + 1, seed, passSampler, threads);
      f.rays = (first.rays + second.rays) / 2.0;
      f.work = f.rays * cost;
      f.preprocessRays = (first.preprocessing + second.preprocessing) / 2.0;
      const std::vector<double> a = first.image(), b = second.image();
      f.noise = pilotNoise(a, b, &skip);
      f.bulkNoise = pilotNoise(a, b, &skip, true);
      double n = 0.0;
      const std::vector<uint8_t>* counted = countedPixels(a, b, &skip);
      f.mean = keptMean(a, b, counted, n);
      if (seeded)  // the records' part of the noise
        measureRecords(*integrator, *other, a,
                       PilotPicture{scene, desc, fillDesc, skip, seed, passSampler, sampler, threads}, f);
      // Both images' rays; a preprocessing not drawn from the seed served both.
      f.pilotRays += first.rays + second.rays - (seeded ? 0.0 : preprocessing);
    }
    spent += f.pilotRays;
    f.seeded = seeded && f.spp > 0;
    figures.push_back(f);
    if (progress) progress(c);
  }
  // A method that has not found the light yet (paths that must hit a bulb behind glass by chance) makes two
  // equally dark pictures: little noise. Its picture's mean falls short of the others', which agree (they all
  // estimate the same image): the shortfall from their median counts as error too.
  std::vector<double> means;
  for (const PilotFigure& f : figures)
    if (f.spp > 0) means.push_back(f.mean);
  if (means.empty()) return figures;
  std::nth_element(means.begin(), means.begin() + ptrdiff_t(means.size() / 2), means.end());
  const double median = means[means.size() / 2];
  // A seeded preprocessing (the cache's fill) is charged at its share of the render: G, the render's work per pilot
  // picture (renderWork), and its fill grown to the render's picture (kFillGrowth), at kFillRayCost a ray, then
  // taken at the pilot picture's share of the render's pixels, as G is.
  const double render = renderWork(budget);
  const double fillPixels = double(fillDesc.width) * double(fillDesc.height);
  const double fillRaysGrowth = std::pow(renderPixels / fillPixels, kFillGrowth);  // the fill's rays, grown
  const double fillGrowth = fillRaysGrowth * double(desc.width) * double(desc.height) / renderPixels;
  for (PilotFigure& f : figures) {
    f.fillSeconds *= fillRaysGrowth / kPilotFillSlowdown;
    if (f.spp == 0 || !(median > 0.0)) continue;
    const double noise = f.noise * f.mean / median, off = (f.mean - median) / median;
    f.error = std::sqrt(noise * noise + off * off);
    f.error = std::max(f.error, kMinError);
    f.efficiency = f.work > 0.0 ? 1.0 / (f.error * f.error * f.work) : 0.0;
    const double bulk = std::max(kMinError, std::hypot(f.bulkNoise * f.mean / median, off));
    f.bulkEfficiency = f.work > 0.0 ? 1.0 / (bulk * bulk * f.work) : 0.0;
    if (!f.seeded) continue;
    // The passes' noise at the passes' work of the render (what its fill leaves); frozen part and bias stay, the
    // frozen part as the render's denser records have it (kRecordsErrorExponent), their own noise as the render's
    // records gather with more rays where that pays (bestRecordSamples).
    const double scale = f.mean / median;
    double pass2 = std::max(0.0, noise * noise - f.frozen * f.frozen * scale * scale);
    // The records' own noise stays at any density; the rest (where they were placed, how they interpolate) falls.
    f.frozenMeasured = f.frozen;
    const double own = f.recordNoise * scale;
    const double placed = std::sqrt(std::max(0.0, f.frozen * f.frozen - f.recordNoise * f.recordNoise)) *
                          std::pow(fillPixels / renderPixels, kRecordsErrorExponent) * scale;
    const double cost = f.rays > 0.0 ? f.work / f.rays : 1.0,
                 fill = f.preprocessRays * fillGrowth * cost * kFillRayCost;
    const double passRays = (f.rays - f.preprocessRays) * cost;
    // The render's passes gain from its stratified samples as passes^−passRate: beyond the 1/√ of more rays, by the
    // render pixel's samples against the pilot pixel's (at the pilot's records' rays).
    const double finer =
        passRays > 0.0 ? (render - fill) / passRays * double(desc.width) * double(desc.height) / renderPixels : 0.0;
    if (finer > 1.0) pass2 *= std::pow(finer, -(2.0 * f.passRate - 1.0));
    f.recordSamples = bestRecordSamples(std::sqrt(pass2), own, placed, off, passRays, fill, render, f.efficiency);
    f.frozen = std::sqrt(own * own / f.recordSamples + placed * placed);
    f.preprocessShare = render > 0.0 ? fill * f.recordSamples / render : 1.0;
  }
  for (PilotFigure& f : figures)
    if (f.efficiency > 0.0 && render > 0.0) f.renderError = 1.0 / std::sqrt(f.efficiency * render);
  return figures;
}

int bestRecordSamples(double passNoise, double own, double placed, double bias, double passRays, double fill,
                      double render, double& efficiency) {
  int best = 1;
  efficiency = -1.0;
  for (int m = 1; m <= kMaxRecordSamples && (m == 1 || fill * m <= kMaxRecordsFillShare * render); m *= 2) {
    const double frozen = std::sqrt(own * own / m + placed * placed);
    const double e = renderEfficiency(std::sqrt(passNoise * passNoise + frozen * frozen), frozen, bias, passRays,
                                      fill * m, render);
    if (e > efficiency) efficiency = e, best = m;
  }
  return best;
}

double recordSamplesForTime(const PilotFigure& f, double seconds) {
  const double m = f.recordSamples;
  if (!(f.fillSeconds > 0.0) || !(seconds > 0.0) || f.fillSeconds * m <= kFillTimeShare * seconds) return m;
  double fewer = m / 2.0;
  while (fewer > kLeastRecordSamples && f.fillSeconds * fewer > kMaxFillShare * seconds) fewer /= 2.0;
  return std::max(fewer, kLeastRecordSamples);
}

double renderEfficiency(double noise, double frozen, double bias, double passRays, double fixed, double render) {
  if (!(fixed < render) || !(passRays > 0.0)) return 0.0;
  const double pass2 = std::max(0.0, noise * noise - frozen * frozen);
  const double e2 = frozen * frozen + bias * bias + pass2 * passRays / (render - fixed);
  // The floor as the others': an error of kMinError after the passes' rays.
  return 1.0 / (std::max(e2, kMinError * kMinError * passRays / render) * render);
}

std::vector<uint8_t> rankedPilotFigures(const std::vector<PilotFigure>& figures, const std::vector<size_t>& robust,
                                        const std::vector<uint8_t>& pathTracer) {
  const size_t n = figures.size();
  // Unmeasured figures rank (their efficiency is 0): the first of equals stays the first.
  std::vector<uint8_t> ranked(n);
  bool otherRanks = false;  // a figure of a method other than the path tracer's ranks by its error
  for (size_t i = 0; i < n; ++i) {
    ranked[i] = figures[i].spp == 0 || figures[i].error <= kUnrankableError;
    otherRanks = otherRanks || (figures[i].spp > 0 && ranked[i] && !(i < pathTracer.size() && pathTracer[i]));
  }
  if (!otherRanks)
    for (size_t i : robust)
      if (i < n && figures[i].spp > 0) ranked[i] = 1;
  // Of the robust ones that rank, the one whose bulk is the most efficient (the first of equals): their figures differ
  // most by the fireflies they meet alike, and which of them a pilot's few passes met is a lottery.
  size_t keep = n;
  for (size_t i : robust)
    if (i < n && figures[i].spp > 0 && ranked[i] && (keep == n || figures[i].bulkEfficiency > figures[keep].bulkEfficiency))
      keep = i;
  for (size_t i : robust)
    if (i < n && figures[i].spp > 0 && i != keep) ranked[i] = 0;
  return ranked;
}

size_t bestPilotFigure(const std::vector<PilotFigure>& figures, const std::vector<size_t>& robust,
                       const std::vector<uint8_t>& pathTracer) {
  return bestRankedFigure(figures, rankedPilotFigures(figures, robust, pathTracer));
}

size_t bestRankedFigure(const std::vector<PilotFigure>& figures, const std::vector<uint8_t>& ranked) {
  size_t best = 0;
  while (best < figures.size() && !ranked[best]) ++best;
  if (best == figures.size()) return 0;  // nothing ranks
  for (size_t i = best + 1; i < figures.size(); ++i)
    if (ranked[i] && figures[i].efficiency > figures[best].efficiency) best = i;
  return best;
}

}  // namespace firstshot
