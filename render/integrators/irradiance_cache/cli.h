#pragma once
/// @file cli.h
/// The irradiance cache's command line (render/integrators/integrator_cli.h; header-only, included by the table
/// in render/integrators/integrator.cpp): its options, the integrator made with them, and its outputs after the
/// render. Of the shared options it reads all but --shoot-firstshot (--patch-nee: in the paths that
/// continue past the last cached bounce).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/util/error.h"
#include "render/integrators/integrator_cli.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/output/film.h"

namespace firstshot {

class IrradianceCacheCli : public IntegratorCli {
 public:
  IrradianceCacheSettings settings;
  std::string ambient = "0", gradients = "on", clampFootprint = "1.5,100", neighbourClamp = "on", miss = "path",
              showRecords;
  bool twoPass = false, onePass = false;
  CLI::Option* ambientOption = nullptr;
  CLI::Option* samplesOption = nullptr;
  bool configured = false;  ///< configure() ran: make() hands the settings to the integrator

  void add(CLI::App& app) override {
    auto onOff = CLI::IsMember({"on", "off"});
    const std::vector<CLI::Option*> declared = {
        app.add_option("--accuracy", settings.accuracy, "irradiance cache: a, the accuracy of eq. 5 (smaller: more records)")
            ->check(CLI::Range(1e-4, 10.0))->capture_default_str(),
        samplesOption = app.add_option("--ic-samples", settings.samples, "irradiance cache: hemisphere samples per "
                                                                         "level-0 record (halved per bounce; not "
                                                                         "given, a --time render takes more where its "
                                                                         "budget pays for them, as a pilot measures)")
            ->check(CLI::Range(8, 1 << 20))->capture_default_str(),
        app.add_option("--bounces", settings.bounces, "irradiance cache: bounces served by the cache: records at path "
                                                      "vertices 0..B-1 (level ℓ uses a·1.4^ℓ); beyond them path tracing, "
                                                      "or --ambient")
            ->check(CLI::Range(0, 16))->capture_default_str(),
        ambientOption = app.add_option("--ambient", ambient, "irradiance cache: radiance assumed past the last bounce, V or "
                                                 "R,G,B (biased; default: the light there is path traced)"),
        app.add_option("--gradients", gradients, "irradiance cache: rotational and translational gradients (Ward & "
                                                 "Heckbert 1992)")
            ->check(onOff)->capture_default_str(),
        app.add_option("--clamp-footprint", clampFootprint, "irradiance cache: MIN,MAX keep each record's valid "
                                                            "domain a*R_i within [MIN, MAX] pixel footprints, or off")
            ->capture_default_str(),
        app.add_option("--neighbour-clamp", neighbourClamp, "irradiance cache: R_i <= R_j + |P_i - P_j| between "
                                                            "neighbouring records")
            ->check(onOff)->capture_default_str(),
        app.add_option("--ic-patch-nee", settings.patchNee, "irradiance cache with --firstshot: patch NEE samples per "
                                                            "hemisphere ray of a record, MIS-combined with the rays (0: off)")
            ->check(CLI::Range(0.0, 64.0))->capture_default_str(),
        app.add_option("--ic-miss", miss, "irradiance cache, two-pass: where a render sample finds no record, take one "
                                          "path from there (unbiased, one sample's rays) or make a record for that "
                                          "sample alone (Ward's method: its hundreds of rays serve one sample)")
            ->check(CLI::IsMember({"path", "record"}))->capture_default_str(),
        app.add_flag("--two-pass", twoPass, "irradiance cache: fill the cache through every pixel first, then render "
                                            "read-only, so the image does not depend on --threads (the default)"),
        app.add_flag("--one-pass", onePass, "irradiance cache: make records while rendering (25-30% less CPU; the "
                                            "image then depends on the order threads make them, and --resume is refused)"),
        app.add_option("--cache-file", settings.cacheFile, "irradiance cache: records read from F if it exists, written "
                                                           "to F after the render"),
        app.add_option("--show-records", showRecords, "irradiance cache: also write the image with the camera-visible "
                                                      "record positions in blue (.png or .exr)"),
    };
    for (const CLI::Option* o : declared) own_.push_back(o->get_name());
  }

  /// Checks the values and keeps the settings for make(). @throws InputError for a bad value.
  void configure(IntegratorSetup& setup) override {
    if (twoPass && onePass) throw InputError("", "--one-pass", "not with --two-pass");
    settings.twoPass = !onePass;
    settings.ambient = parseColor(ambient, "--ambient");
    settings.pathContinuation = ambientOption->count() == 0;  // --ambient given: Ward's ambient term instead
    settings.gradients = gradients == "on";
    settings.neighbourClamp = neighbourClamp == "on";
    settings.missRecords = miss == "record";
    if (clampFootprint == "off") {
      settings.footprintMin = 0.0f;
      settings.footprintMax = std::numeric_limits<float>::infinity();
    } else {
      const Color v = parseColor(clampFootprint, "--clamp-footprint", 2);
      if (!(v.x >= 0.0f) || !(v.y >= v.x) || !(v.y > 0.0f))
        throw InputError("", "--clamp-footprint", "expected MIN,MAX with 0 <= MIN <= MAX, MAX > 0 (pixels), or off");
      settings.footprintMin = v.x;
      settings.footprintMax = v.y;
    }
    if (!showRecords.empty()) {
      const std::string ext = std::filesystem::path(showRecords).extension().string();
      if (ext != ".png" && ext != ".PNG" && ext != ".exr" && ext != ".EXR")
        throw InputError(showRecords, "--show-records", "unsupported image type (expected .png or .exr)");
    }
    if (!settings.cacheFile.empty()) {
      const auto dir = std::filesystem::path(settings.cacheFile).parent_path();
      if (!dir.empty() && !std::filesystem::is_directory(dir))
        throw InputError(settings.cacheFile, "--cache-file", "the folder does not exist");
    }
    settings.seed = setup.seed;
    settings.threads = setup.threads;
    settings.sampler = setup.sampler;  // the two-pass fill traces the render's camera samples
    settings.quiet = setup.quiet;  // the fill's progress (rank 0's alone: the integrator knows its ranks)
    configured = true;
  }

  std::unique_ptr<Integrator> make(const IntegratorOptions& options) const override {
    auto ic = std::make_unique<IrradianceCacheIntegrator>(options);
    if (configured) ic->setSettings(settings);
    return ic;
  }

  std::string inputFile() const override { return settings.cacheFile; }
  int recordSamples() const override { return settings.samples; }
  void setRecordSamples(int samples) override {
    if (!samplesOption || samplesOption->count() == 0) settings.samples = samples;
  }

  /// After the render: writes the cache file and the record image (unless @p film is null: sensors),
  /// and prints a summary.
  void finish(const Integrator& integrator, const Film* film, float exposure, double renderSeconds,
              bool quiet) const override {
    const auto* ic = dynamic_cast<const IrradianceCacheIntegrator*>(&integrator);
    if (!ic) return;
    if (!settings.cacheFile.empty()) ic->saveCache(settings.cacheFile);
    if (!showRecords.empty() && film) ic->writeRecordImage(*film, showRecords, exposure);
    if (quiet) return;
    const IrradianceCacheStats s = ic->stats();
    std::string levels;
    for (size_t l = 0; l < s.perLevel.size(); ++l) levels += fmt::format("{}{}", l ? " + " : "", s.perLevel[l]);
    const size_t made = s.records - s.loaded;
    const double seconds = renderSeconds + s.fillSeconds;
    fmt::print(stderr, "irradiance cache: {} records ({} by level), {} loaded, {} new ({:.0f} records/s), {} hemisphere "
               "rays per level-0 record", s.records, levels.empty() ? "0" : levels, s.loaded, made,
               seconds > 0 ? double(made) / seconds : 0.0, settings.samples);
    if (settings.twoPass)
      fmt::print(stderr, "; fill {:.2f} s, {:.3f} Mrays in {} sweep(s), {} of its records made twice; in the {}: {} "
                 "lookups without a record took a path", s.fillSeconds, double(s.fillRays) * 1e-6, s.fillRounds,
                 s.fillDuplicates, film ? "render" : "sensor estimate", s.missPaths);
    if (s.privateRecords > 0) fmt::print(stderr, ", {} private records", s.privateRecords);
    if (s.fillCutAt > 0)
      fmt::print(stderr, "; the fill stopped at three quarters of the render's time after {} of {} pixels of sweep {} "
                 "(samples its records do not cover took a path)", s.fillCutAt, s.fillPixels, s.fillRounds);
    fmt::print(stderr, "\n");
  }

 protected:
  std::vector<std::string> shared() const override {
    using namespace integrator_option;
    return {kPrimary, kLightSampler, kPatchNee, kLightVisibility, kTableVisibility, kLuminaires};
  }

 private:
  /// "v" or "a,b[,c]" → up to @p n values (a single value fills every component).
  static Color parseColor(const std::string& text, const char* what, int n = 3) {
    std::vector<float> v;
    size_t pos = 0;
    try {
      while (pos <= text.size()) {
        const size_t comma = text.find(',', pos);
        const std::string part = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
        size_t used = 0;
        v.push_back(std::stof(part, &used));
        if (used != part.size()) throw std::invalid_argument(part);
        if (comma == std::string::npos) break;
        pos = comma + 1;
      }
    } catch (const std::exception&) {
      throw InputError("", what, "not a number list: \"" + text + "\"");
    }
    if (v.size() == 1) v.assign(size_t(n), v[0]);
    if (int(v.size()) != n) throw InputError("", what, fmt::format("expected 1 or {} values, got \"{}\"", n, text));
    Color c(0.0f);
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(v[size_t(i)]) || v[size_t(i)] < 0.0f) throw InputError("", what, "values must be finite and >= 0");
      c[i] = v[size_t(i)];
    }
    return c;
  }
};

}  // namespace firstshot
