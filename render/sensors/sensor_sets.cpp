// Sensor sets: points files (rtrace -I style), grids on a horizontal work plane and on a named quad.
#include <fmt/core.h>

#include <cmath>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>

#include "common/util/error.h"
#include "render/sensors/sensors.h"

namespace firstshot {

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

namespace {

/// True if shape @p index, named @p shapeName ("shapes[i]" or "shapes[i] (\"user\")"), is @p name.
bool shapeIs(const std::string& shapeName, size_t index, const std::string& name) {
  const std::string place = fmt::format("shapes[{}]", index);
  return name == shapeName || name == place || shapeName == fmt::format("{} (\"{}\")", place, name);
}

}  // namespace

SensorSet gridOnQuad(const SceneDesc& scene, const std::string& spec) {
  const char* opt = "--grid-quad";
  const auto c2 = spec.rfind(','), c1 = c2 == std::string::npos || c2 == 0 ? std::string::npos : spec.rfind(',', c2 - 1);
  if (c1 == std::string::npos || c1 == 0)
    throw InputError("", opt, fmt::format("expected NAME,offset,spacing, got \"{}\"", spec));
  const std::string name = spec.substr(0, c1);
  double v[2];
  const std::string fields[2] = {spec.substr(c1 + 1, c2 - c1 - 1), spec.substr(c2 + 1)};
  for (int k = 0; k < 2; ++k) {
    size_t used = 0;
    try {
      v[k] = std::stod(fields[k], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || fields[k].find_first_not_of(" \t", used) != std::string::npos)
      throw InputError("", opt, fmt::format("expected NAME,offset,spacing, got \"{}\"", spec));
    if (!std::isfinite(v[k]) || std::abs(v[k]) > 1e30) throw InputError("", opt, "a value is not a finite number");
  }
  const double offset = v[0], spacing = v[1];
  if (!(spacing > 0)) throw InputError("", opt, "the spacing must be positive");

  int found = -1;
  for (size_t i = 0; i < scene.shapes.size(); ++i)
    if (shapeIs(scene.shapes[i].name, i, name)) {
      if (found >= 0)
        throw InputError(scene.file, opt, fmt::format("\"{}\" names both {} and {}", name, scene.shapes[size_t(found)].name,
                                                      scene.shapes[i].name));
      found = int(i);
    }
  if (found < 0) throw InputError(scene.file, opt, fmt::format("no shape named \"{}\"", name));
  const ShapeDesc& s = scene.shapes[size_t(found)];
  if (s.type != ShapeType::Quad || s.faces.size() != 1 || s.faces[0].count != 4)
    throw InputError(scene.file, opt, fmt::format("{} is not a quad (a planar convex quad shape)", s.name));

  Vec3d q[4];
  for (int k = 0; k < 4; ++k) q[k] = s.vertices[s.faces[0].v[k]];
  const Vec3d cross = glm::cross(q[1] - q[0], q[2] - q[0]) + glm::cross(q[2] - q[0], q[3] - q[0]);
  const double len = glm::length(cross);
  if (!(len > 0)) throw InputError(scene.file, opt, fmt::format("{} has no area", s.name));
  const Vec3d n = cross / len;  // counter-clockwise seen from the front
  const double lu = 0.5 * (glm::length(q[1] - q[0]) + glm::length(q[2] - q[3]));
  const double lv = 0.5 * (glm::length(q[3] - q[0]) + glm::length(q[2] - q[1]));
  const double nu = std::max(1.0, std::round(lu / spacing)), nv = std::max(1.0, std::round(lv / spacing));
  if (nu * nv > 1e7) throw InputError("", opt, fmt::format("{} × {} points is more than 10⁷", nu, nv));

  SensorSet set;
  set.name = "grid-quad " + spec;
  set.columns = int(nu), set.rows = int(nv);  // a raster in the quad's frame: u along v0→v1, v along v0→v3
  for (int j = 0; j < int(nv); ++j)
    for (int i = 0; i < int(nu); ++i) {
      const double u = (i + 0.5) / nu, w = (j + 0.5) / nv;
      const Vec3d p = (1 - u) * (1 - w) * q[0] + u * (1 - w) * q[1] + u * w * q[2] + (1 - u) * w * q[3] + offset * n;
      set.sensors.push_back({Vec3(p), Vec3(n)});
    }
  return set;
}

}  // namespace firstshot
