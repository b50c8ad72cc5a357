#pragma once
/// @file sensors.h
/// Irradiance and illuminance at sensor points: a sensor is a point x with a unit
/// normal n, on a surface or in free space (a work plane). Its irradiance
///     E(x, n) = ∫_{H(n)} L_in(x, ω) cos θ dω      (W/m² per RGB channel)
/// is estimated per sample as
///     π · NEE(x, n)  +  π · L_r(y → x),
/// the first term next-event estimation to the lights (nextEvent, render/lights/next_event.h, with a Lambertian of
/// albedo 1, so f·cos/pdf = cos/(π pdf); small lights of a first-shot table sampled exactly, as at a
/// camera-visible point; MIS off, so the second term leaves out the emission it meets directly), its lights
/// chosen by the integrator's own light sampler over its first-shot lighting (Integrator::lightSampler: built
/// once by the integrator's preprocessing and shared, never a second copy),
/// the second one cosine-distributed direction ω (pdf cos θ/π) whose radiance arriving at x is the
/// integrator's Li() along the ray minus the emission of a light it meets first (counted by NEE), or minus the
/// radiance of the scene's sky or environment map where the ray leaves the scene (NEE counted that too).
/// Where the light sampler samples luminaires (the path tracer's, with the luminaires whose light leaves mostly
/// through glass: render/cli/render_command.cpp), the sensor is instead a vertex of a path: NEE with MIS (the
/// luminaires' specular light and exit patches among the emitters), and the cosine ray walked from that non-delta
/// vertex (Integrator::LiFromSensor), which weighs what it meets against that NEE and counts a luminaire's exit light
/// where it enters its box, not its lights inside (docs/luminaires.md, "Sensors").
/// The integrator is the path tracer or the irradiance cache (requireSensorIntegrator): the
/// estimator needs Li() per ray, which the splatting and per-pass ones do not have. The irradiance
/// cache is filled from the sensors' own rays (preprocessSensors), not from the camera's pixels.
///
/// Sample s of sensor i is keyed by (seed, i, s), the samples of a sensor are summed in sample
/// order: results never depend on the thread count.
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/util/comm.h"
#include "common/util/error.h"
#include "common/util/math.h"
#include "render/integrators/integrator.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// One sensor: position (m) and unit normal of the receiving side.
struct Sensor {
  Vec3 p{0.0f};
  Vec3 n{0.0f, 1.0f, 0.0f};
};

/// A named group of sensors (a points file or a grid), summarised together.
struct SensorSet {
  std::string name;  ///< the points file or the grid's specification
  std::vector<Sensor> sensors;
  /// A grid's cells along x and z (--grid), or along the quad's edges v0→v1 and v0→v3 (--grid-quad);
  /// the sensors are stored row by row. 0 for a points file.
  int columns = 0, rows = 0;
};

/// Reads a points file: one sensor per line "x y z nx ny nz" (like rtrace -I); blank lines and
/// lines starting with '#' are skipped; the normal is normalised.
/// @throws InputError naming the file and line for a malformed line, a zero or non-finite value,
/// a missing file or a file without sensors.
SensorSet readSensorFile(const std::string& path);

/// A grid on a horizontal work plane: the rectangle [x0, x1] × [z0, z1] at y = height, normal +y,
/// cut into cells of about @p spacing m (rounded so the cells fill the rectangle), one sensor at
/// each cell's centre. @p spec is the text "x0,z0,x1,z1,height,spacing".
/// @throws InputError for a malformed spec, x1 <= x0, z1 <= z0, spacing <= 0 or more than 10⁷ points.
SensorSet parseGrid(const std::string& spec);

/// A grid on a named quad of the scene (a work plane given by a shape): @p spec is
/// "NAME,offset,spacing" (NAME may hold commas; the last two fields are numbers). NAME is a quad
/// shape's `name` key or its place "shapes[i]". The quad's edges v0→v1 and v0→v3 are cut into
/// about |edge|/spacing cells (the mean of opposite edges, rounded, at least 1); one sensor at
/// each cell's centre (bilinear in the quad's corners), moved @p offset m along the quad's
/// normal (the front side, right-hand rule; after the shape's transform and flip_normals),
/// which is every sensor's normal. Any orientation.
/// @throws InputError (naming --grid-quad) for a malformed spec, spacing <= 0, an unknown or
/// ambiguous name, a shape that is not one planar convex quad, or more than 10⁷ points.
SensorSet gridOnQuad(const SceneDesc& scene, const std::string& spec);

/// Estimated irradiance at one sensor.
struct SensorResult {
  Color irradiance{0.0f};  ///< mean RGB irradiance, W/m²
  double lux = 0;          ///< mean illuminance, lm/m²
  double stderrLux = 0;    ///< standard error of lux: σ/√n with σ from the samples
  uint64_t samples = 0;
};

/// E_min, E_avg, E_max and uniformity U0 = E_min/E_avg of a set, in lux.
struct SensorSummary {
  double minLux = 0, avgLux = 0, maxLux = 0, uniformity = 0;
};
SensorSummary summarize(const std::vector<SensorResult>& results);

struct SensorOptions {
  int samples = 256;        ///< per sensor (ignored when timeLimit > 0)
  double timeLimit = 0;     ///< seconds; > 0: passes of `batch` samples per sensor until the time is up
  int batch = 16;           ///< samples per sensor per pass with timeLimit
  uint64_t seed = 1;
  /// How the samples' numbers are drawn (common/sampling/rng.h; --sampler): in Sobol' mode the samples
  /// s = 0, 1, ... of one sensor are the indices of its own stratified sequence.
  SamplerMode sampler = SamplerMode::Independent;
  int threads = 0;          ///< 0 = one per core; results do not depend on it
  bool quiet = true;        ///< no progress bar
  double efficacy = 179.0;  ///< lm/W (common/lights/photometry.h)
  /// preprocessSensors: samples per sensor whose rays fill a caching integrator's records
  /// (the estimate's own first samples, so they find their records).
  int fillSamples = 4;
  /// preprocessSensors: the angular footprint of a sensor ray (rad), for a caching integrator's
  /// footprint clamp (as the camera's pixel angle for camera rays).
  double rayAngle = 0.05;
  /// The ranks of an MPI run (common/util/comm.h; null: this process alone): each estimates the sensors
  /// dealt to it and rank 0 receives every sensor's sums (the other ranks' results hold only their
  /// own sensors). With a time limit rank 0's clock decides. The results do not depend on the ranks.
  Comm* comm = nullptr;
};

struct SensorStats {
  uint64_t samples = 0;    ///< per sensor
  uint64_t rays = 0;
  uint64_t nonFinite = 0;  ///< samples that were NaN or Inf (recorded as 0)
  double seconds = 0;
};

/// @throws InputError unless @p integrator is the path tracer or the irradiance cache.
void requireSensorIntegrator(const Integrator& integrator);

/// Prepares @p integrator for estimateSensors() at @p sensors (instead of preprocess()):
/// Integrator::preprocessRays with one task per sensor, its samples 0 .. fillSamples − 1 keyed
/// as estimateSensors() keys them. The irradiance cache (two-pass) fills its records from those
/// rays, deterministically; the path tracer only preprocesses.
void preprocessSensors(Integrator& integrator, const RenderScene& scene, const std::vector<Sensor>& sensors,
                       const SensorOptions& options);

/// Estimates the irradiance at @p sensors. @p integrator must be preprocessed for @p scene (by
/// preprocessSensors for these sensors, or preprocess() for a path tracer) and
/// estimate radiance per ray (IntegratorKind::Sampling). Polls the interrupt flag between passes.
std::vector<SensorResult> estimateSensors(const Integrator& integrator, const RenderScene& scene,
                                          const std::vector<Sensor>& sensors, const SensorOptions& options,
                                          SensorStats* stats = nullptr);

}  // namespace firstshot
