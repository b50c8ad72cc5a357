#pragma once
/// @file sensors_cli.h
/// firstshot-render's sensor mode (header-only, included by render/cli/render_command.cpp, which links CLI11):
/// --sensors FILE and --grid SPEC choose the points, --samples/--time the effort, -o OUT.csv or
/// OUT.json receives one row per sensor; the summary per set (E_min, E_avg, E_max, U0) goes to
/// stdout and into the JSON (docs/cli.md, "Illuminance at sensors"; docs/photometry.md). --daylight-factor
/// renders under the CIE overcast sky alone and adds each sensor's daylight factor (render/sensors/daylight_factor.h).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "common/lights/photometry.h"
#include "common/util/atomic_file.h"
#include "common/util/error.h"
#include "render/lights/light_sampler.h"
#include "render/sensors/daylight_factor.h"
#include "render/sensors/sensors.h"

namespace firstshot {

struct SensorsCli {
  std::string pointsFile;
  std::vector<std::string> grids;
  std::vector<std::string> quadGrids;
  int samples = 256;
  double efficacy = photometry::kEfficacy;
  bool daylightFactor = false;  ///< --daylight-factor
  double outsideLux = 0;        ///< its E_outside (lux), set by the caller from daylightFactorScene(); 0: no DF
  CLI::Option* pointsOption = nullptr;
  CLI::Option* gridOption = nullptr;
  CLI::Option* quadOption = nullptr;
  /// Called by run() with the sets and every sensor's illuminance (lx, in the sets' order; with --daylight-factor
  /// its DF in percent) before the outputs are written (the false-colour picture of a grid,
  /// render/cli/falsecolor_cli.h).
  std::function<void(const std::vector<SensorSet>&, const std::vector<double>&)> onResults;

  void add(CLI::App& app) {
    pointsOption = app.add_option("--sensors", pointsFile, "sensor mode: points file, one sensor per line "
                                                            "\"x y z nx ny nz\" (like rtrace -I); -o gets .csv or .json");
    gridOption = app.add_option("--grid", grids, "sensor mode: grid x0,z0,x1,z1,height,spacing on the plane y = height "
                                                 "(normal +y), one sensor per cell centre; may be repeated");
    quadOption = app.add_option("--grid-quad", quadGrids, "sensor mode: grid NAME,offset,spacing on the scene's quad shape "
                                                          "NAME (its name key or shapes[i]), offset m along its normal, "
                                                          "one sensor per cell centre with the quad's normal; may be repeated");
    app.add_option("--samples", samples, "sensor mode: samples per sensor")->check(CLI::Range(1, 1 << 30))
        ->capture_default_str();
    app.add_option("--efficacy", efficacy, "sensor mode: luminous efficacy in lm/W turning W/m² into lux "
                                           "(docs/photometry.md)")
        ->check(CLI::Range(1e-6, 1e6))->capture_default_str();
    app.add_flag("--daylight-factor", daylightFactor,
                 "sensor mode: daylight factor DF = E/E_outside in % under the scene's sky, which must be "
                 "cie-overcast, alone (sun, lights and emission switched off); E_outside = the sky's unobstructed "
                 "horizontal illuminance (docs/photometry.md)");
  }
  bool active() const { return pointsOption->count() > 0 || gridOption->count() > 0 || quadOption->count() > 0; }

  /// Checks the options that do not mix with the sensor mode and the outputs (.csv or .json).
  void checkOptions(const CLI::App& app, const std::vector<std::string>& outputs) const {
    if (!active()) {
      if (app.count("--samples")) throw InputError("", "--samples", "only with --sensors, --grid or --grid-quad");
      if (daylightFactor) throw InputError("", "--daylight-factor", "only with --sensors, --grid or --grid-quad");
      // --efficacy also serves --units luminance and --falsecolor: checked in render/cli/falsecolor_cli.h
      return;
    }
    for (const char* o : {"--spp", "--preview", "--checkpoint", "--resume", "--aov", "--exposure", "--show-records"})
      if (app.get_option_no_throw(o) && app.count(o)) throw InputError("", o, "not available with --sensors/--grid");
    if (app.count("--time") && app.count("--samples")) throw InputError("", "--samples", "give --samples or --time");
    if (outputs.empty()) throw InputError("", "--output", "sensor mode needs -o OUT.csv or OUT.json");
    for (const auto& out : outputs) {
      const std::string ext = std::filesystem::path(out).extension().string();
      if (ext != ".csv" && ext != ".json") throw InputError(out, "", "sensor output must be .csv or .json");
      const auto dir = std::filesystem::path(out).parent_path();
      if (!dir.empty() && !std::filesystem::is_directory(dir)) throw InputError(out, "", "the output folder does not exist");
    }
  }

  /// Reads the points and grids (before the scene is built, so bad input fails fast).
  std::vector<SensorSet> sets() const {
    std::vector<SensorSet> s;
    if (!pointsFile.empty()) s.push_back(readSensorFile(pointsFile));
    for (const auto& g : grids) s.push_back(parseGrid(g));
    return s;
  }
  /// Appends the --grid-quad sets to @p s (they need the scene's shapes).
  void addQuadGrids(const SceneDesc& scene, std::vector<SensorSet>& s) const {
    for (const auto& g : quadGrids) s.push_back(gridOnQuad(scene, g));
  }

  /// A luminaire whose light leaves through glass, which @p integrator's light sampler takes as lights (`--luminaires
  /// off`, `--light-sampler all`): that light reaches a sensor only where a ray refracts into the
  /// lamp by chance, and never from a point light. Said once on stderr (rank 0), not silently.
  static void warnOfLuminairesTakenAsLights(const Integrator& integrator, const RenderScene& scene,
                                            const SensorOptions& options) {
    const LightSampler* lights = integrator.lightSampler();
    if (!lights || lights->hasLuminaires() || scene.luminaires().empty() || (options.comm && !options.comm->root()))
      return;
    for (const Luminaire& l : scene.luminaires().items())
      if (luminance(l.specularPower) > 0.0f) {
        fmt::print(stderr,
                   "firstshot-render: warning: the sensors take luminaire {}'s lights as lights ({}): its light through "
                   "glass reaches them only where a ray refracts into the lamp (none from a point light); "
                   "--luminaires on with the light tree samples it\n",
                   l.name, integrator.name());
        return;
      }
  }

  /// Preprocesses @p integrator for the sensors, estimates every set and writes @p outputs; prints
  /// the summaries on stdout.
  int run(Integrator& integrator, const RenderScene& scene, const std::vector<SensorSet>& sets,
          const std::vector<std::string>& outputs, SensorOptions options) const {
    options.samples = samples;
    options.efficacy = efficacy;
    std::vector<Sensor> all;
    for (const auto& s : sets) all.insert(all.end(), s.sensors.begin(), s.sensors.end());
    const auto start = std::chrono::steady_clock::now();
    preprocessSensors(integrator, scene, all, options);
    warnOfLuminairesTakenAsLights(integrator, scene, options);
    const double prepSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    SensorStats st;
    const std::vector<SensorResult> results = estimateSensors(integrator, scene, all, options, &st);
    if (options.comm && !options.comm->root()) return 0;  // rank 0 holds every sensor's result and writes them
    std::vector<SensorSummary> summaries;
    size_t at = 0;
    for (const auto& s : sets) {
      summaries.push_back(summarize(setResults(results, at, s)));
      at += s.sensors.size();
    }
    if (onResults) {
      std::vector<double> values;
      for (const auto& r : results) values.push_back(outsideLux > 0 ? daylightFactorPercent(r.lux, outsideLux) : r.lux);
      onResults(sets, values);
    }
    for (const auto& out : outputs)
      writeAtomically(out, [&](const std::string& tmp) {
        std::ofstream f(tmp);
        if (out.ends_with(".json")) writeJson(f, sets, results, summaries, st);
        else writeCsv(f, all, results);
        if (!f) throw std::runtime_error(out + ": write failed");
      });
    if (outsideLux > 0)
      fmt::print("E_outside {:.6g} lx (the CIE overcast sky on an unobstructed horizontal plane)\n", outsideLux);
    at = 0;
    for (size_t k = 0; k < sets.size(); ++k) {
      fmt::print("{}: {} sensors, E_min {:.6g} lx, E_avg {:.6g} lx, E_max {:.6g} lx, U0 {:.4f}", sets[k].name,
                 sets[k].sensors.size(), summaries[k].minLux, summaries[k].avgLux, summaries[k].maxLux,
                 summaries[k].uniformity);
      if (outsideLux > 0) {
        const DaylightFactorSummary d = summarizeDaylightFactor(setResults(results, at, sets[k]), outsideLux);
        fmt::print(", DF_min {:.4g}%, DF_avg {:.4g}%, DF_max {:.4g}%, DF_median {:.4g}%", d.min, d.avg, d.max,
                   d.median);
      }
      fmt::print("\n");
      at += sets[k].sensors.size();
    }
    if (st.nonFinite > 0)
      fmt::print(stderr, "firstshot-render: warning: {} samples were NaN or Inf and were recorded as 0\n", st.nonFinite);
    if (!options.quiet && integrator.hasRecords())  // its cache was filled from the sensors' rays
      fmt::print(stderr, "{} preprocess for the sensors: {:.3f} s\n", integrator.name(), prepSeconds);
    if (!options.quiet)
      fmt::print(stderr, "{} sensors at {} samples in {:.3f} s: {:.2f} Mrays/s\n", all.size(), st.samples, st.seconds,
                 st.seconds > 0 ? double(st.rays) / st.seconds * 1e-6 : 0.0);
    return 0;
  }

  /// The results of set @p s, which start at @p at in @p results.
  static std::vector<SensorResult> setResults(const std::vector<SensorResult>& results, size_t at, const SensorSet& s) {
    return {results.begin() + long(at), results.begin() + long(at + s.sensors.size())};
  }

  /// The columns of a row: with a daylight factor two more, df_percent and stderr_df_percent.
  std::string columns(const char* quote, const char* sep) const {
    std::string c;
    for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "irradiance_r", "irradiance_g", "irradiance_b",
                             "illuminance_lux", "stderr_lux", "df_percent", "stderr_df_percent"}) {
      if (outsideLux <= 0 && std::string(name).find("df_") != std::string::npos) break;
      c += (c.empty() ? "" : sep) + std::string(quote) + name + quote;
    }
    return c;
  }
  void writeRow(std::ostream& f, const Sensor& s, const SensorResult& r, const char* sep) const {
    f << fmt::format("{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}{}{:.9g}", s.p.x, sep,
                     s.p.y, sep, s.p.z, sep, s.n.x, sep, s.n.y, sep, s.n.z, sep, r.irradiance.x, sep, r.irradiance.y,
                     sep, r.irradiance.z, sep, r.lux, sep, r.stderrLux);
    if (outsideLux > 0)
      f << fmt::format("{}{:.9g}{}{:.9g}", sep, daylightFactorPercent(r.lux, outsideLux), sep,
                       daylightFactorPercent(r.stderrLux, outsideLux));
  }
  void writeCsv(std::ostream& f, const std::vector<Sensor>& sensors, const std::vector<SensorResult>& results) const {
    f << columns("", ",") << '\n';
    for (size_t i = 0; i < sensors.size(); ++i) {
      writeRow(f, sensors[i], results[i], ",");
      f << '\n';
    }
  }
  void writeJson(std::ostream& f, const std::vector<SensorSet>& sets, const std::vector<SensorResult>& results,
                 const std::vector<SensorSummary>& summaries, const SensorStats& st) const {
    f << "{\n  \"columns\": [" << columns("\"", ", ") << "],\n";
    if (outsideLux > 0) f << fmt::format("  \"E_outside_lux\": {:.9g},\n", outsideLux);
    f << fmt::format("  \"samples\": {},\n  \"sets\": [", st.samples);
    size_t at = 0;
    for (size_t k = 0; k < sets.size(); ++k) {
      const SensorSummary& m = summaries[k];
      std::string name;
      for (char c : sets[k].name) name += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
      f << fmt::format("{}\n    {{\"name\": \"{}\", \"E_min\": {:.9g}, \"E_avg\": {:.9g}, \"E_max\": {:.9g}, "
                       "\"U0\": {:.9g},",
                       k ? "," : "", name, m.minLux, m.avgLux, m.maxLux, m.uniformity);
      if (outsideLux > 0) {
        const DaylightFactorSummary d = summarizeDaylightFactor(setResults(results, at, sets[k]), outsideLux);
        f << fmt::format(" \"DF_min\": {:.9g}, \"DF_avg\": {:.9g}, \"DF_max\": {:.9g}, \"DF_median\": {:.9g},",
                         d.min, d.avg, d.max, d.median);
      }
      f << "\n     \"rows\": [";
      for (size_t i = 0; i < sets[k].sensors.size(); ++i, ++at) {
        f << (i ? ",\n       [" : "\n       [");
        writeRow(f, sets[k].sensors[i], results[at], ", ");
        f << "]";
      }
      f << "]}";
    }
    f << "\n  ]\n}\n";
  }
};

}  // namespace firstshot
