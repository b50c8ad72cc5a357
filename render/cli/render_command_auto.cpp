// firstshot-render's --integrator auto: the choice of the integrator (render/loop/integrator_pilot.h).
#include <fmt/core.h>

#include <algorithm>
#include <chrono>

#include "common/util/progress.h"
#include "render/cli/render_command.h"
#include "render/loop/checkpoint.h"

namespace firstshot {

namespace {

/// The path tracer among @p candidates as the user would get it without a table's options (else the first).
const PilotCandidate& pathOrFirst(const std::vector<PilotCandidate>& candidates) {
  for (const PilotCandidate& c : candidates)
    if (c.integrator == "path" && c.patchNee == PatchNee::Off) return c;
  for (const PilotCandidate& c : candidates)
    if (c.integrator == "path") return c;
  return candidates.front();
}

/// Why the pilot has no figures of @p f (@p imageRays: the rays of one of the first candidate's images).
std::string skipReason(const PilotFigure& f, double imageRays) {
  switch (f.skip) {
    case PilotSkip::Outgrown: return "its preprocessing alone outgrows the pilot";
    case PilotSkip::PassCost:
      return fmt::format("not tried: one pass takes {:.1f} times an image's rays", f.rays / std::max(1.0, imageRays));
    case PilotSkip::Share:
      return fmt::format("not tried: its images would take the pilot past its {:.0f}% of the render", 100 * kPilotShare);
    default: return "not tried: as above";
  }
}

}  // namespace

void RenderCommand::leaveTableUnread() {
  tableUnused_ = true;
  renderScene_.reset();  // built again, without the table
}

PilotPlan RenderCommand::pilotPlan(size_t candidates, int& spp) const {
  // With --time the samples are not known before the render: the scene's, or the time at a fixed rate of
  // kTimeRate camera samples per second, whichever is more (the pilot must not depend on the machine).
  constexpr double kTimeRate = 250000.0;
  const double pixels = double(scene_.camera.width) * double(scene_.camera.height);
  spp = spp_ > 0 ? spp_
        : timeLimit_ > 0 ? int(std::min(1e6, std::max<double>(scene_.settings.spp, timeLimit_ * kTimeRate / pixels)))
                         : scene_.settings.spp;
  // Where the time sized it, the render's work is the time at a nominal ray rate (planPilot).
  const bool timed = spp_ <= 0 && timeLimit_ > 0 && timeLimit_ * kTimeRate / pixels > scene_.settings.spp;
  return planPilot(scene_.camera, spp, candidates, timed ? timeLimit_ : 0.0);
}

PilotFactory RenderCommand::pilotFactory(const IntegratorOptions& base) {
  return [this, base](const PilotCandidate& c, uint64_t seed) {
    IntegratorOptions io = base;
    io.patchNee = c.patchNee;
    io.shootFromPatches = c.shootFromPatches;
    if (c.everyLight) io.lightSampler = LightStrategy::All;
    IntegratorSetup setup{&app_, &scene_, seed, threads_, spp_, samplerMode(), true};
    IntegratorCli& cli = integrators_.cli(c.integrator);
    cli.configure(setup);
    return cli.make(io);
  };
}

void RenderCommand::sizeRecords() {
  IntegratorCli& cli = integrators_.chosen();
  if (checkpoint_.resume && !preview_ && !sensors_.active()) {  // the rays of the render being resumed
    for (const auto& [name, value] : readCheckpointKey(checkpoint_.path(outputs_)))
      if (name == kRecordSamplesKey) cli.setRecordSamples(std::stoi(value));
    return;
  }
  if (app_.count(kRecordSamplesKey) || timeLimit_ <= 0 || preview_ || sensors_.active()) return;
  IntegratorOptions base = integrators_.options(maxDepth());
  base.comm = nullptr;  // every rank measures the same and sizes alike
  PilotCandidate alone;
  alone.integrator = integrators_.name;
  alone.patchNee = base.patchNee;
  int spp = 0;
  const PilotPlan plan = pilotPlan(2, spp);  // the share of a pilot of two
  if (!plan.run) return;
  const auto start = std::chrono::steady_clock::now();
  if (!renderScene_) buildRenderScene();
  const std::vector<PilotFigure> figures =
      runPilot(*renderScene_, nullptr, {alone}, plan, pilotFactory(base), seed(), samplerMode(), threads_);
  pilotSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int pilotRays = cli.recordSamples();
  if (!quiet_)
    fmt::print(stderr,
               "firstshot-render: {}: {} hemisphere rays per record for this render's budget (a pilot of {:.2f} s: its "
               "fill projected to {:.1f}% of the render's rays; --ic-samples fixes them)\n",
               integrators_.name, pilotRays * figures.front().recordSamples, pilotSeconds_,
               100.0 * figures.front().preprocessShare);
  fitRecordsToTime(figures.front(), pilotRays);
}

void RenderCommand::fitRecordsToTime(const PilotFigure& f, int pilotRays) {
  IntegratorCli& cli = integrators_.chosen();
  const int nominal = pilotRays * f.recordSamples;
  cli.setRecordSamples(nominal);
  if (timeLimit_ <= 0 || checkpoint_.active() || comm_.size() > 1) return;  // as limitPreprocessSeconds
  const double seconds = timeLimit_ - pilotSeconds_;
  const double m = recordSamplesForTime(f, seconds);
  if (m >= f.recordSamples) return;
  const int rays = std::max(1, int(std::lround(pilotRays * m)));
  cli.setRecordSamples(rays);
  if (!quiet_)
    fmt::print(stderr,
               "firstshot-render: {}: {} hemisphere rays per record, not {}: on this machine the pilot's fills project "
               "the render's to {:.1f} s at {} (at {}: {:.1f} s) of the {:.1f} s left\n",
               integrators_.name, rays, nominal, f.fillSeconds * f.recordSamples, nominal, rays,
               f.fillSeconds * m, seconds);
}

void RenderCommand::resolveIntegrator() {
  if (!integrators_.isAuto() && integrators_.chosen().recordSamples() > 0) sizeRecords();
  if (!integrators_.isAuto()) return;
  // A table's options (--patch-nee, --shoot-firstshot) change nothing where it replaces no light (a table of
  // luminaires alone): their variants would be the same pictures at twice the pilot's cost.
  if (!fsdPath_.empty()) buildRenderScene();
  const bool replaces = renderScene_ && renderScene_->firstShot() && !renderScene_->firstShot()->replacedLights.empty();
  // Sensors and the preview start with the table: a choice without it is the pilot's, on the camera's pictures.
  const bool tableGiven = renderScene_ && renderScene_->firstShot() && !sensors_.active() && !preview_;
  const bool luminaires = tableGiven && !renderScene_->luminaires().empty();
  const bool manyLights = scene_.lights.size() + (scene_.sky || scene_.environment ? 1 : 0) > 1;
  const std::vector<PilotCandidate> candidates = integrators_.autoCandidates(
      app_, replaces, tableGiven, luminaires, manyLights, scene_.sky || scene_.environment, scene_.file);
  auto say = [&](const std::string& text) {
    if (!quiet_) fmt::print(stderr, "firstshot-render: --integrator auto: {}\n", text);
  };
  if (candidates.size() == 1) {
    integrators_.choose(candidates.front());
    say(candidates.front().label() + " (the only integrator that reads the options given)");
    return;
  }
  if (checkpoint_.resume && !preview_ && !sensors_.active()) {  // the choice of the render being resumed
    PilotCandidate c = candidates.front();
    for (const auto& [name, value] : readCheckpointKey(checkpoint_.path(outputs_))) {
      if (name == "integrator") c.integrator = value;
      if (name == integrator_option::kPatchNee)
        c.patchNee = value == "off" ? PatchNee::Off : value == "first" ? PatchNee::First : PatchNee::Every;
      if (name == integrator_option::kShootFirstShot) c.shootFromPatches = value == "patches";
      if (name == kTableUnusedKey) c.table = false;
      if (name == integrator_option::kLightSampler) c.everyLight = value == "all";
      if (name == kRecordSamplesKey) integrators_.cli(c.integrator).setRecordSamples(std::stoi(value));
    }
    c.variesPatchNee = c.variesShoot = false;
    integrators_.choose(c);
    if (!c.table) leaveTableUnread();
    say(c.label() + " (the choice of the render in the checkpoint)");
    return;
  }
  if (sensors_.active() || preview_) {  // the pilot compares pictures of the camera's view
    integrators_.choose(pathOrFirst(candidates));
    say(pathOrFirst(candidates).label() + (preview_ ? " (the preview starts with it; keys switch integrators)"
                                                    : " (for sensors; the pilot compares pictures)"));
    return;
  }
  int spp = 0;
  const PilotPlan plan = pilotPlan(candidates.size(), spp);
  if (!plan.run) {
    integrators_.choose(pathOrFirst(candidates));
    say(fmt::format("{} ({} x {} at {} spp leaves no room for a pilot)", pathOrFirst(candidates).label(),
                    scene_.camera.width, scene_.camera.height, spp));
    return;
  }

  const auto start = std::chrono::steady_clock::now();
  if (!renderScene_) buildRenderScene();
  // The scene as without --firstshot, for the candidates that leave the table unread.
  std::unique_ptr<RenderScene> withoutTable;
  if (std::any_of(candidates.begin(), candidates.end(), [](const PilotCandidate& c) { return !c.table; }))
    withoutTable = std::make_unique<RenderScene>(scene_, patchSize_);
  IntegratorOptions base = integrators_.options(maxDepth());
  base.comm = nullptr;  // every rank runs the same pilot and makes the same choice
  base.lightPathsCap = plan.lightPaths;  // the render's own are not capped (--light-paths given is kept)
  const PilotFactory make = pilotFactory(base);
  std::vector<PilotFigure> figures;
  {
    Progress progress("integrator pilot", candidates.size(), quiet_);
    figures = runPilot(*renderScene_, withoutTable.get(), candidates, plan, make, seed(), samplerMode(), threads_,
                       [&](size_t) { progress.advance(); });
  }
  pilotSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Where no other method's figure ranks, the path tracer on the scene as given ranks whatever its error: without the
  // table if one was given (its gain unmeasured, the render exact), NEE by the light tree or to every light
  // (rankedPilotFigures).
  const bool anyUnread = std::any_of(candidates.begin(), candidates.end(), [](const PilotCandidate& c) { return !c.table; });
  std::vector<size_t> robust;
  std::vector<uint8_t> pathTracer(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) {
    pathTracer[i] = candidates[i].integrator == "path";
    // The scene as given: the candidates that leave the table unread where there are such, else every one.
    if (pathTracer[i] && candidates[i].table == !anyUnread && candidates[i].patchNee == PatchNee::Off) robust.push_back(i);
  }
  const std::vector<uint8_t> ranked = rankedPilotFigures(figures, robust, pathTracer);
  const size_t best = bestRankedFigure(figures, ranked);
  integrators_.choose(candidates[best]);
  // The cache's records gathered with the rays the pilot found the render's budget pays for.
  std::vector<int> recordSamples(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i)
    recordSamples[i] = integrators_.cli(candidates[i].integrator).recordSamples();
  if (!candidates[best].table) {
    tableUnused_ = true;
    renderScene_ = std::move(withoutTable);
  }
  if (!quiet_) printPilot(candidates, figures, plan, spp, ranked, robust, best, recordSamples);
  if (figures[best].seeded) fitRecordsToTime(figures[best], recordSamples[best]);
}

void RenderCommand::printPilot(const std::vector<PilotCandidate>& candidates, const std::vector<PilotFigure>& figures,
                               const PilotPlan& plan, int spp, const std::vector<uint8_t>& ranked,
                               const std::vector<size_t>& robust, size_t best,
                               const std::vector<int>& recordSamples) const {
  // The pilot's rays against the render's, priced at the first candidate's rays per camera sample (as the plan).
  double pilotRays = 0.0;
  for (const PilotFigure& f : figures) pilotRays += f.pilotRays;
  const PilotFigure& chosen = figures[best];
  const double pixels = double(scene_.camera.width) * double(scene_.camera.height);
  const double renderRays = pixels * double(spp) * figures.front().rays /
                            (double(plan.width) * double(plan.height) * double(std::max(1, figures.front().spp)));
  fmt::print(stderr,
             "firstshot-render: --integrator auto: pilot at {} x {}, each setting's two images at equal rays, {:.2f} s "
             "({:.1f}% of the rays of {} x {} at {} spp):\n  {:<42} {:>5} {:>9} {:>9} {:>12} {:>11} {:>10}\n",
             plan.width, plan.height, pilotSeconds_, renderRays > 0 ? 100.0 * pilotRays / renderRays : 0.0,
             scene_.camera.width, scene_.camera.height, spp, "setting", "spp", "rel.noise", "rel.error", "Mrays/image",
             "efficiency", "render err");
  const double top = chosen.efficiency;
  // A robust candidate that does not rank where another does lost to it on their bulk (rankedPilotFigures).
  const bool robustRanks = std::any_of(robust.begin(), robust.end(), [&](size_t k) { return ranked[k] != 0; });
  const auto bulkLost = [&](size_t i) {
    return robustRanks && std::find(robust.begin(), robust.end(), i) != robust.end();
  };
  for (size_t i = 0; i < candidates.size(); ++i)
    if (figures[i].spp == 0)
      fmt::print(stderr, "  {:<42} {:>5} {:>9} {:>9} {:>12.3f} ({})\n", candidates[i].label(), "-", "-", "-",
                 figures[i].rays * 1e-6,
                 skipReason(figures[i], figures.front().rays));
    else
      fmt::print(stderr, "  {:<42} {:>5} {:>9.4f} {:>9.4f} {:>12.3f} {:>11.3g} {:>10.4f}{}\n", candidates[i].label(),
                 figures[i].spp, figures[i].noise, figures[i].error, figures[i].rays * 1e-6,
                 top > 0 ? figures[i].efficiency / top : 0.0, figures[i].renderError,
                 i == best ? " *"
                 : ranked[i] ? ""
                 : bulkLost(i) ? " (not ranked: the other light sampler's bulk is the more efficient)"
                               : " (not ranked: its error exceeds its mean)");
  const CameraDesc fill = pilotFillCamera(scene_.camera, plan);
  for (size_t i = 0; i < candidates.size(); ++i)
    if (figures[i].spp > 0 && figures[i].preprocessShare > 0.0)
      fmt::print(stderr,
                 "  {}: filled at {} x {}; at {} hemisphere rays per record its fill projected to {:.1f}% of the "
                 "render's rays, its records' error {:.4f} (more passes leave it; {:.4f} as measured at {}, of which "
                 "their own noise {:.4f}; the {:.1f}% of the pixels where a sample they miss took a path left "
                 "out), its passes' noise falling as passes^-{:.2f}, its efficiency the render's\n",
                 candidates[i].label(), fill.width, fill.height, recordSamples[i] * figures[i].recordSamples,
                 100.0 * figures[i].preprocessShare, figures[i].frozen, figures[i].frozenMeasured, recordSamples[i],
                 figures[i].recordNoise, 100.0 * figures[i].missShare, figures[i].passRate);
  fmt::print(stderr, "firstshot-render: --integrator auto chose {} (efficiency = 1/(error² · rays), relative to it; render err: "
             "the render's relative error so projected){}{}\n",
             candidates[best].label(),
             chosen.error > kUnrankableError
                 ? "; its figure errs by more than its mean, but no other method's ranks: the path tracer on the scene "
                   "as given ranks whatever its error"
                 : "",
             tableUnused_ ? "; the table given is not read: the render is the scene's as without --firstshot" : "");
}

}  // namespace firstshot
