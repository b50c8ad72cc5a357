// Sensor sets: points files (rtrace -I style) and grids on a horizontal work plane.
#include <fmt/core.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "render/sensors.h"

namespace fs {

SensorSet readSensorFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "", "cannot open the sensor file");
  SensorSet set;
  set.name = path;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ls(line);
    double v[6];
    int k = 0;
    while (k < 6 && ls >> v[k]) ++k;
    std::string rest;
    const std::string where = fmt::format("line {}", number);
    if (k < 6 || (ls >> rest))
      throw InputError(path, where, "expected six numbers \"x y z nx ny nz\"");
    for (double x : v)
      if (!std::isfinite(x) || std::abs(x) > 1e30) throw InputError(path, where, "a value is not a finite number");
    const double len = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
    if (!(len > 1e-12)) throw InputError(path, where, "the normal (nx ny nz) has zero length");
    set.sensors.push_back({Vec3(float(v[0]), float(v[1]), float(v[2])),
                           Vec3(float(v[3] / len), float(v[4] / len), float(v[5] / len))});
  }
  if (set.sensors.empty()) throw InputError(path, "", "the sensor file holds no sensors");
  return set;
}

SensorSet parseGrid(const std::string& spec) {
  double v[6];
  std::string text = spec;
  for (char& c : text)
    if (c == ',') c = ' ';
  std::istringstream in(text);
  int k = 0;
  while (k < 6 && in >> v[k]) ++k;
  std::string rest;
  if (k < 6 || (in >> rest))
    throw InputError("", "--grid", fmt::format("expected x0,z0,x1,z1,height,spacing, got \"{}\"", spec));
  for (double x : v)
    if (!std::isfinite(x) || std::abs(x) > 1e30) throw InputError("", "--grid", "a value is not a finite number");
  const double x0 = v[0], z0 = v[1], x1 = v[2], z1 = v[3], y = v[4], spacing = v[5];
  if (!(x1 > x0) || !(z1 > z0)) throw InputError("", "--grid", "needs x1 > x0 and z1 > z0");
  if (!(spacing > 0)) throw InputError("", "--grid", "the spacing must be positive");
  const double nx = std::max(1.0, std::round((x1 - x0) / spacing)), nz = std::max(1.0, std::round((z1 - z0) / spacing));
  if (nx * nz > 1e7) throw InputError("", "--grid", fmt::format("{} × {} points is more than 10⁷", nx, nz));
  SensorSet set;
  set.name = "grid " + spec;
  set.columns = int(nx), set.rows = int(nz);
  const double dx = (x1 - x0) / nx, dz = (z1 - z0) / nz;
  for (int j = 0; j < int(nz); ++j)
    for (int i = 0; i < int(nx); ++i)
      set.sensors.push_back({Vec3(float(x0 + (i + 0.5) * dx), float(y), float(z0 + (j + 0.5) * dz)), Vec3(0, 1, 0)});
  return set;
}

}  // namespace fs
