#pragma once
/// @file falsecolor_cli.h
/// firstshot-render's photometric outputs (header-only, included by render/cli/render_command.cpp,
/// which links CLI11): --units luminance (EXR outputs in cd/m²) and --falsecolor OUT.png with --falsecolor-scale,
/// --falsecolor-range and --falsecolor-contours, of the image's luminance or of a --grid's
/// illuminance, or its daylight factor with --daylight-factor (docs/cli.md, "Photometric outputs"; docs/photometry.md;
/// render/output/falsecolor.h).
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "common/util/error.h"
#include "render/output/falsecolor.h"
#include "render/output/film.h"
#include "render/sensors/sensors.h"

namespace firstshot {

struct FalseColorCli {
  std::string units = "radiance";
  std::string output, scale, range;
  int contours = 0;

  void add(CLI::App& app) {
    app.add_option("--units", units, "EXR outputs: radiance (R, G, B in W/(m² sr)) or luminance (one channel Y in "
                                     "cd/m², --efficacy · Y; docs/photometry.md)")
        ->check(CLI::IsMember({"radiance", "luminance"}))->capture_default_str();
    app.add_option("--falsecolor", output, "false-colour picture OUT.png of the image's luminance (cd/m²) or, with "
                                           "--grid, of the first grid's illuminance (lx; with --daylight-factor its "
                                           "DF in %, 0 to 10% unless --falsecolor-range), with a labelled legend");
    app.add_option("--falsecolor-scale", scale, "log or linear (default: log for images, linear for grids)");
    app.add_option("--falsecolor-range", range, "MIN,MAX of the colour scale in the legend's units (default: the 1st "
                                                "to 99th percentile, widened to nice numbers)");
    app.add_option("--falsecolor-contours", contours, "draw iso-lines at about N nice levels (the legend's ticks)")
        ->check(CLI::Range(1, 50));
  }
  bool active() const { return !output.empty(); }

  /// Checks the options before any work: the picture's name and folder, the scale, the range, the
  /// font, and which options go with the sensor mode (@p sensorMode, @p sets: its sensor sets).
  void checkOptions(const CLI::App& app, bool sensorMode, const std::vector<SensorSet>& sets,
                    const std::vector<std::string>& outputs) const {
    if (!active())
      for (const char* o : {"--falsecolor-scale", "--falsecolor-range", "--falsecolor-contours"})
        if (app.count(o)) throw InputError("", o, "only with --falsecolor");
    if (app.count("--efficacy") && !sensorMode && units != "luminance" && !active())
      throw InputError("", "--efficacy", "only with --sensors, --grid, --units luminance or --falsecolor");
    if (sensorMode && app.count("--units")) throw InputError("", "--units", "not available with --sensors/--grid");
    if (!active()) return;
    if (app.count("--preview")) throw InputError("", "--falsecolor", "not available with --preview");
    const std::filesystem::path out(output);
    if (out.extension() != ".png" && out.extension() != ".PNG")
      throw InputError(output, "--falsecolor", "the false-colour picture must be a .png file");
    if (!out.parent_path().empty() && !std::filesystem::is_directory(out.parent_path()))
      throw InputError(output, "--falsecolor", "the output folder does not exist");
    for (const auto& o : outputs)
      if (std::filesystem::weakly_canonical(o) == std::filesystem::weakly_canonical(out))
        throw InputError(output, "--falsecolor", "the false-colour picture would overwrite the -o output");
    if (sensorMode && !gridSet(sets) && !app.count("--grid-quad"))  // quad grids join once the scene is loaded
      throw InputError("", "--falsecolor", "in sensor mode it needs a --grid or --grid-quad");
    if (!scale.empty() && scale != "log" && scale != "linear")
      throw InputError("", "--falsecolor-scale", "expected log or linear, got \"" + scale + "\"");
    options(sensorMode);  // checks the range
    falsecolor::requireFont();
  }

  /// The drawing options; a grid defaults to a linear scale, an image to a log one. A daylight factor
  /// (@p daylightFactor) has the fixed default range 0–10% (0.1–10% on a log scale), so pictures compare.
  /// @throws InputError for a malformed --falsecolor-range or one that does not fit the scale.
  falsecolor::Options options(bool grid, bool daylightFactor = false) const {
    falsecolor::Options o;
    o.scale = scale.empty() ? (grid ? falsecolor::Scale::Linear : falsecolor::Scale::Log)
                            : scale == "log" ? falsecolor::Scale::Log : falsecolor::Scale::Linear;
    o.contours = contours;
    if (range.empty() && daylightFactor) {
      o.autoRange = false;
      o.range = {o.scale == falsecolor::Scale::Log ? 0.1 : 0.0, 10.0};
    }
    if (range.empty()) return o;
    std::string text = range;
    for (char& c : text)
      if (c == ',') c = ' ';
    std::istringstream in(text);
    double lo = 0, hi = 0;
    std::string rest;
    if (!(in >> lo >> hi) || (in >> rest) || !std::isfinite(lo) || !std::isfinite(hi))
      throw InputError("", "--falsecolor-range", "expected MIN,MAX (two numbers), got \"" + range + "\"");
    if (!(hi > lo)) throw InputError("", "--falsecolor-range", "needs MAX > MIN");
    if (o.scale == falsecolor::Scale::Log && !(lo > 0))
      throw InputError("", "--falsecolor-range", "a log scale needs MIN > 0");
    o.autoRange = false;
    o.range = {lo, hi};
    return o;
  }

  /// Writes the picture of a rendered image's luminance, cd/m² at @p efficacy (lm/W).
  void writeImage(const Film& film, double efficacy) const {
    const falsecolor::Field f{film.width(), film.height(), film.luminance(efficacy), "cd/m\xC2\xB2"};
    falsecolor::writePng(output, falsecolor::draw(f, options(false)));
  }

  /// Writes the picture of the first grid of @p sets; @p values holds every set's sensors in order: illuminance in
  /// lux, or with @p daylightFactor the daylight factor in percent.
  void writeGrid(const std::vector<SensorSet>& sets, const std::vector<double>& values, bool daylightFactor) const {
    size_t at = 0;
    for (const auto& s : sets) {
      if (s.columns > 0) {
        const auto first = values.begin() + long(at);
        falsecolor::Field f{s.columns, s.rows, {first, first + long(s.sensors.size())}, daylightFactor ? "DF %" : "lx"};
        falsecolor::writePng(output, falsecolor::draw(f, options(true, daylightFactor)));
        return;
      }
      at += s.sensors.size();
    }
  }

 private:
  static bool gridSet(const std::vector<SensorSet>& sets) {
    for (const auto& s : sets)
      if (s.columns > 0) return true;
    return false;
  }
};

}  // namespace firstshot
