#pragma once
/// @file integrator_pilot.h
/// `--integrator auto` (firstshot-render's default): a short pilot renders a small picture of the camera's view
/// with each candidate integrator, measures its efficiency and hands the render to the best (docs/integrators.md,
/// "The method chosen for the user").
///
/// Each candidate renders the pilot picture twice, with seeds s and s + 1, and every image gets the same rays: what
/// the first candidate (the path tracer) traces in the plan's samples per pixel (at least 2 passes and at most 256
/// each; light tracing's passes take at most PilotPlan::lightPaths light paths per pixel, so that two fit), so that
/// each is measured at equal rays, and a method of cheap samples at many samples, where stratified
/// samples have paid off (a pilot of equal samples took light tracing for the path tracer's better on the Cornell
/// box: at 4 spp its error is its edges' and stratification's). Its noise is the RMS over pixels and
/// channels of the two images' difference / √2, relative to the picture's mean: one image's error, bias aside
/// (pixels brighter than 5 means clamped there: pilotNoise).
/// Pixels where the camera sees an emitter or a mirror or glass (4 rays per pixel, thin panes seen through) are left
/// out of the noise and the mean: every method takes them alike (light tracing gives them to the path tracer), and a
/// lamp's edge aliases at a pilot's few samples. The other pixels count unclamped, as the render's error is measured:
/// a firefly of a thousand means is what makes a path tracer's picture of a lamp in a bowl unusable (only the path
/// tracer's two light samplers are compared by their bulk, clamped: rankedPilotFigures).
/// Its work is the rays it traced for one image (its preprocessing's too, the irradiance cache's fill), counted,
/// not timed, the path tracer's with patch NEE at 2.5 each (its patch sampling's time per ray, which no ray count
/// shows); efficiency = 1 / (error² · work), the inverse of the work to reach a given error, where the error
/// adds to the noise how far the picture's mean falls from the candidates' median (PilotFigure). Images and ray
/// counts do not depend on the threads (render/loop/renderer.h), so the choice is the same on every machine for
/// a seed.
/// An integrator whose preprocessing draws on the seed (the irradiance cache's fill) is made for a coarser picture
/// (pilotFillCamera: a sixteenth of the pixels), its four images and two fills in the rays of two images, and renders
/// the pilot picture over those records, a sample that they do not cover taking one path. Its records' error does not shrink
/// with more passes: its noise is split into that frozen part (a third image, the second fill's records under the
/// first image's passes, against the first), projected to the render's denser records, and the passes' (its passes
/// take independent samples), and its efficiency is the render's, its fill charged at its share
/// of the render's work (grown from the fill's picture to the render's as pixels^kFillGrowth, its rays at kFillRayCost
/// each), not of a pilot image (PilotFigure::efficiency); the render's work is its samples at the first candidate's
/// rays per sample, or where --time sized it, the time at kTimeRaysRate.
/// The pilot picture has at most 48 × 48 pixels, the camera's aspect and field; each candidate's two images take 4%
/// of the render's camera samples divided among the candidates, priced at the first candidate's rays per sample
/// (with --time T: of the scene's samples per pixel or T × 250,000 camera samples, whichever is more: fixed rates,
/// so that the pilot does not depend on the machine). Below 4 samples per pixel of a 16 × 16 picture there is no
/// pilot: the path tracer renders. Past the first candidate, one pass over a sixteenth of the pixels tells what a
/// pass costs: a candidate whose two passes would take more than four images' rays (NEE to each of many lights) is
/// not tried, nor one (not the cache) whose images would take the pilot past kPilotShare (5%) of the render's rays
/// (PilotSkip); the cache's two fills stop (PilotSkip::Outgrown) where they would leave less of that share than its
/// own images and each later candidate's at two passes, and the candidates after a costly one share what is left.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/sampling/rng.h"
#include "common/scene/scene_desc.h"
#include "render/integrators/integrator.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// One setting the pilot tries: an integrator of integratorTable() and the shared options it is tried with.
struct PilotCandidate {
  std::string integrator;             ///< --integrator NAME
  PatchNee patchNee = PatchNee::Off;  ///< --patch-nee (for the integrators that read it)
  bool shootFromPatches = true;       ///< --shoot-firstshot patches (light, bdpt with a table)
  bool variesPatchNee = false;        ///< the label names --patch-nee (there were variants of it)
  bool variesShoot = false;           ///< the label names --shoot-firstshot
  /// Reads the table given with --firstshot; false: renders the scene as if none were given (its small lights as
  /// lights, no luminaires), a candidate only where a table was given.
  bool table = true;
  /// --light-sampler all: next-event estimation to every light at every vertex, not one chosen by the light tree.
  bool everyLight = false;
  /// The candidate as options: "path", "path --patch-nee every", "light --shoot-firstshot off", "path, no table".
  std::string label() const;
};

/// Of the render's rays (at the first candidate's rays per camera sample), the whole pilot's at most: a candidate
/// whose images would pass it is not tried (PilotSkip::Share).
inline constexpr double kPilotShare = 0.05;

/// Why a candidate has no figures (PilotFigure::spp 0).
enum class PilotSkip {
  None,      ///< measured
  Outgrown,  ///< its preprocessing alone (the cache's fill) outgrew the pilot
  Variant,   ///< the same integrator's preprocessing outgrew it as another candidate's
  PassCost,  ///< its kMinPasses passes would take many times an image's rays
  Share,     ///< its images would take the pilot past its share of the render (never the cache's)
};

/// What the pilot measured of one candidate.
struct PilotFigure {
  /// Passes (samples per pixel) of each of its two images; 0: not measured, its preprocessing alone (the
  /// irradiance cache's fill) took more than two images' rays and more than would take the whole render once
  /// projected to it (rays: that one image's; 0 for the same integrator's other variants, which are then not tried),
  /// or it was not tried (skip).
  int spp = 0;
  double noise = 0;       ///< relative RMS error of one pilot image (above)
  double mean = 0;        ///< the mean of its two pictures (the pixels the noise counts), W/(m² sr)
  /// √(noise'² + bias²), relative to the median m of the candidates' means: noise' = noise · mean / m, bias =
  /// (mean − m) / m (a method that has not found the light yet is dark, not noisy).
  double error = 0;
  double rays = 0;        ///< rays per pilot image, preprocessing included
  /// The work they count: rays, the path tracer's with patch NEE at 2.5 each (the patch sampling's time), and where
  /// candidates without the table are measured too, a table reader's at 1.35 times that (its lookups' time)
  double work = 0;
  double preprocessRays = 0;  ///< of those, the preprocessing's
  PilotSkip skip = PilotSkip::None;  ///< why not measured (PassCost: rays are one pass's, as the probe tells)
  /// Every ray the pilot traced for it (its share): its images, its preprocessing, and past the first candidate the
  /// pass over pilotFillCamera's picture that told what one pass costs.
  double pilotRays = 0;
  bool seeded = false;        ///< measured with a seeded preprocessing (the cache's fill, over pilotFillCamera)
  /// A seeded preprocessing's (the cache's records'): the part of noise' that more passes over the same records do
  /// not reduce, · mean / m, as the render's records would leave it: the relative noise between the first image and
  /// the second fill's records under the first image's passes, × (fill pixels / render pixels)^0.5; 0 for the
  /// others.
  double frozen = 0;
  /// Of the frozen part as measured (frozenMeasured, before it is projected), what the records' own noise makes:
  /// √2 × the relative noise between the first image and its passes over its records each perturbed by their own
  /// error (Integrator::perturbPreprocessing). It does not fall with more records; the rest does. 0 for the others.
  double recordNoise = 0;
  double frozenMeasured = 0;  ///< the frozen part as measured at the fill's picture
  /// A seeded preprocessing's: the share of the counted pixels left out of the frozen part, those where a sample
  /// either fill's records miss took a path (which the render's passes average away, pass noise); 0 for the others.
  double missShare = 0;
  /// A seeded preprocessing's: its passes' noise falls as passes^−this with the render's sampler, over the same
  /// records (its fill's picture at 4 and 32 passes, two seeds; within [0.5, 1]); its projection to the render gains
  /// so beyond the 1/√ of more rays. 0.5 for the others (not measured).
  double passRate = 0.5;
  double bulkNoise = 0;       ///< noise with pixels clamped at kPilotClamp image means (pilotNoise's clamp)
  /// A seeded preprocessing's: how many times the hemisphere rays per record of the pilot's fill the render's should
  /// take (1, 2, 4, … 16): the records' own noise² falls as 1/m and the fill grows m times, and the m of the best
  /// efficiency is taken (frozen, preprocessShare and efficiency are the render's with it). 1 for the others.
  int recordSamples = 1;
  /// A seeded preprocessing's rays projected to the render, as a fraction of the render's rays (0 for the others).
  double preprocessShare = 0;
  /// A seeded preprocessing's: the render's fill at the pilot's hemisphere rays per record, in seconds of this
  /// machine: the pilot's two fills' mean time grown as their rays are to the render's picture (kFillGrowth), less
  /// what a ray of the pilot's small fill costs more (kPilotFillSlowdown); 0 for the others. It decides only the rays
  /// per record under --time (recordSamplesForTime), never the choice.
  double fillSeconds = 0;
  /// 1 / (error² · work), the error at least 10⁻⁴ (methods that exact are equals); 0 for a black picture. For a
  /// seeded preprocessing, the render's: 1 / (e² · G), G the render's rays per pilot picture and e² = frozen² + bias² + (noise'² − frozen²) · (its passes' rays) / (G −
  /// its preprocessing at the render's scale): the fill charged at its share of the render, not of a pilot image;
  /// 0 where that takes the whole render.
  double efficiency = 0;
  /// The efficiency of its bulk: 1 / (e² · work), e its noise with pixels clamped at kPilotClamp image means (the
  /// fireflies, which the path tracer's variants without the table meet alike, left out) and its mean's distance
  /// from the others', as error; what rankedPilotFigures compares those variants by. 0 where not measured.
  double bulkEfficiency = 0;
  /// The relative error the render is projected to reach with it: √(1 / (efficiency · G)), G the render's work per
  /// pilot picture (its time at kTimeRaysRate where --time sized it), so at the nominal ray rate, not this machine's;
  /// 0 where not measured.
  double renderError = 0;
};

/// The pilot's picture and samples.
struct PilotPlan {
  bool run = false;           ///< false: too small a budget for a pilot
  int width = 0, height = 0;  ///< pixels of the pilot picture
  int spp = 0;                ///< samples per pixel of the first candidate's images (the others: at equal rays)
  /// Light tracing's light paths per pixel and pass at most (IntegratorOptions::lightPathsCap): spp / 4, at least 1,
  /// so that its two passes, each a camera sample and its light paths per pixel, take about the rays of the others'.
  int lightPaths = 1;
  int renderSpp = 0;          ///< samples per pixel of the render the pilot is for
  /// The render's work in ray-equivalents where it is given as a time (--time): its seconds at a nominal
  /// kTimeRaysRate rays per second; 0: renderSpp at the first candidate's rays per sample. Only a seeded
  /// preprocessing's share of the render depends on it.
  double renderWork = 0;
  /// Camera samples of one candidate's two images at the first candidate's price.
  uint64_t samples() const { return uint64_t(width) * uint64_t(height) * uint64_t(spp) * 2; }
};

/// Rays per second of one thread that a render given a time is taken to trace: the path tracer's at 128 × 128 on one
/// thread ran at 2.7–7.4 Mrays/s on the public scenes and 2–11 on the shipped ones (median about 5); fixed, so that the
/// pilot does not depend on the machine or the threads.
inline constexpr double kTimeRaysRate = 4.0e6;

/// The pilot for a render of @p spp samples per pixel through @p camera, among @p candidates candidates; with
/// @p seconds > 0 (a render given a time), its work is also taken as @p seconds at kTimeRaysRate (renderWork).
PilotPlan planPilot(const CameraDesc& camera, int spp, size_t candidates, double seconds = 0.0);

/// @p camera with the pilot picture's size (same view, aspect and field).
CameraDesc pilotCamera(const CameraDesc& camera, const PilotPlan& plan);

/// The picture a seeded preprocessing (the irradiance cache's fill) is made for in the pilot: the pilot picture's
/// sides / 4, at least 4 pixels each (its passes render the pilot picture itself, Integrator::preprocessFor).
CameraDesc pilotFillCamera(const CameraDesc& camera, const PilotPlan& plan);

/// Makes a candidate's integrator, configured for seed @p seed, before preprocessing.
using PilotFactory = std::function<std::unique_ptr<Integrator>(const PilotCandidate& candidate, uint64_t seed)>;

/// Renders every candidate's two pilot images and measures them (in candidates' order): those that read the table
/// in @p scene, the others (PilotCandidate::table false) in @p withoutTable, the same scene built without it (required
/// if there are such candidates). The pixels left out are @p scene's. @p threads: 0 = one per core. @p progress, if
/// set, is called after each candidate with its index.
std::vector<PilotFigure> runPilot(const RenderScene& scene, const RenderScene* withoutTable,
                                  const std::vector<PilotCandidate>& candidates, const PilotPlan& plan,
                                  const PilotFactory& make, uint64_t seed, SamplerMode sampler, int threads,
                                  const std::function<void(size_t)>& progress = {});

/// The relative noise of one image from two images @p a and @p b of independent seeds (interleaved RGB, the same
/// size): RMS of (a − b)/√2 over pixels and channels / the mean m of (a + b)/2; 0 if m is not positive. With
/// @p skip (one entry per pixel), the pixels marked 1 are left out of both. Without it (or where it leaves no pixel
/// with light), values are first clamped at 5 m, where a display that shows the mean as mid-grey (18%) turns white:
/// a lamp seen directly, whose edge pixels alias at a pilot's few samples, then counts as the white it is shown as.
/// @p clamp: clamped at 5 m with @p skip too (the bulk's noise, PilotFigure::bulkNoise).
double pilotNoise(const std::vector<double>& a, const std::vector<double>& b,
                  const std::vector<uint8_t>* skip = nullptr, bool clamp = false);

/// The pilot picture's pixels that the camera sees as they are (1): where one of 4 rays per pixel (the centres of
/// its 2 × 2 strata) first meets, past thin panes, an emitter or a delta surface (a mirror, glass).
std::vector<uint8_t> pixelsSeenAsTheyAre(const RenderScene& scene, const CameraDesc& camera);

/// The efficiency at the render of a method with a fixed cost (a seeded preprocessing, the irradiance cache's
/// fill), per pilot picture: 1 / (e² · @p render), e² = @p frozen² + @p bias² + (@p noise² − @p frozen²) ·
/// @p passRays / (@p render − @p fixed): @p noise (relative, the frozen part included) measured after @p passRays
/// rays of passes, @p fixed the preprocessing's rays at the render's scale, @p render the render's rays; 0 where
/// @p fixed takes them all; e² at least 10⁻⁸ · @p passRays / @p render (an error of 10⁻⁴ after the passes, the floor
/// of PilotFigure::error: methods that exact are equals). Without a fixed cost or a frozen part,
/// 1 / (noise² · passRays): what a method without preprocessing gets.
double renderEfficiency(double noise, double frozen, double bias, double passRays, double fixed, double render);

/// How many times the pilot's hemisphere rays per record the render's records should take (1, 2, 4, … 16, their fill
/// at most kMaxRecordsFillShare, 0.75, of the render's work beyond 1): the m of the best renderEfficiency (the least
/// of equals, into @p efficiency) when the records' own noise @p own falls as 1/√m, their placement's error @p placed stays and the
/// fill @p fill grows m times; @p passNoise the passes' noise after @p passRays (all relative; rays as
/// renderEfficiency's).
int bestRecordSamples(double passNoise, double own, double placed, double bias, double passRays, double fill,
                      double render, double& efficiency);

/// The share of a --time render's seconds past which its fill stops with what it made (Integrator::
/// limitPreprocessSeconds); the pixels it did not reach are path traced.
inline constexpr double kFillTimeShare = 0.75;

/// The multiple of the pilot's hemisphere rays per record the render's records take on this machine with @p seconds
/// left: f.recordSamples (the choice at the nominal ray rate) where its fill, as f.fillSeconds projects it, ends
/// within kFillTimeShare of them; else the largest of its halves, down to kLeastRecordSamples, whose fill takes at
/// most kMaxFillShare of them (kLeastRecordSamples where none does). A fill stopped at kFillTimeShare leaves its
/// later pixels to the path tracer, which in a room lit through a lamp's bowl is hundreds of times noisier; fewer
/// rays per record only double their own noise² at each halving.
double recordSamplesForTime(const PilotFigure& f, double seconds);

/// A pilot figure's relative error (PilotFigure::error: its noise and its mean's distance from the others') above
/// which it measures little but its few largest samples: more than its mean. Such a figure is not ranked (Veach MIS:
/// fireflies off the glossy plates, 0.8-25 at 2-4 passes, its choice a lottery between methods 10-65 times apart at
/// equal time; the cache's noise 0.66 there once, its mean 5.4 times off the others').
inline constexpr double kUnrankableError = 1.0;

/// Which figures rank (1): those that err by at most kUnrankableError (and the unmeasured, whose efficiency is 0);
/// and where no figure of another method than the path tracer's (@p pathTracer[i] 0 or absent) ranks so, the
/// measured ones of @p robust (the caller's: the path tracer on the scene as given, without the table, by either
/// light sampler) whatever their error. Light tracing's, BDPT's and the cache's figures mislead by their tails (Veach
/// MIS: a lottery between methods 10-65 times apart); the path tracer's variants without the table are exact and
/// robust alike, a choice among them costs little whichever way their figures fall, and a scene whose every figure is
/// dim and noisy at the pilot's few passes (the classroom: 0.75-2.2 at 4-5 passes) still has them ranked.
std::vector<uint8_t> rankedPilotFigures(const std::vector<PilotFigure>& figures, const std::vector<size_t>& robust = {},
                                        const std::vector<uint8_t>& pathTracer = {});

/// Index of the most efficient figure among those that rank (rankedPilotFigures; the first of equals; 0 if none
/// ranks or has light).
size_t bestPilotFigure(const std::vector<PilotFigure>& figures, const std::vector<size_t>& robust = {},
                       const std::vector<uint8_t>& pathTracer = {});
/// The same from the figures that rank as rankedPilotFigures gave them (@p ranked).
size_t bestRankedFigure(const std::vector<PilotFigure>& figures, const std::vector<uint8_t>& ranked);

}  // namespace firstshot
