// Zero-area and duplicate faces skipped, one line per input file (common/scene/skipped_faces.h).
#include "common/scene/skipped_faces.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <numeric>
#include <tuple>

#include <tbb/parallel_sort.h>

#include "common/scene/scene_shapes.h"
#include "common/util/error.h"

namespace firstshot {
namespace {

/// Whether validateScene would refuse @p s: a non-finite vertex, a face of other than 3 or 4 vertices or with an
/// index out of range. Such shapes are not touched, so that the error is reported.
bool malformed(const ShapeDesc& s) {
  for (const Vec3d& p : s.vertices)
    if (!isFinite(p)) return true;
  for (const Face& f : s.faces) {
    if (f.count != 3 && f.count != 4) return true;
    for (int i = 0; i < f.count; ++i)
      if (f.v[i] >= s.vertices.size()) return true;
  }
  return false;
}

/// A face by the ids of its vertex positions, rotated to its smallest form, and its vertex count.
using FaceKey = std::array<uint32_t, 5>;

/// For each vertex, the smallest index of a vertex at the same position (sorting, not hashing: fast and exact).
std::vector<uint32_t> positionIds(const std::vector<Vec3d>& v) {
  std::vector<uint32_t> order(v.size()), id(v.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto less = [&](uint32_t a, uint32_t b) {  // equal positions in index order: a total order, deterministic
    return std::tie(v[a].x, v[a].y, v[a].z, a) < std::tie(v[b].x, v[b].y, v[b].z, b);
  };
  tbb::parallel_sort(order.begin(), order.end(), less);
  for (size_t i = 0; i < order.size(); ++i)
    id[order[i]] = i > 0 && v[order[i]] == v[order[i - 1]] ? id[order[i - 1]] : order[i];
  return id;
}

/// Counts of one input file.
struct FileCounts {
  std::string source;  ///< the mesh file, or "" for the scene file's own shapes
  size_t faces = 0, zeroArea = 0, duplicates = 0;
  std::vector<std::string> dropped;  ///< shapes left without faces
};

/// Removes the zero-area and duplicate faces of @p s, adding to @p c.
void skipFaces(ShapeDesc& s, FileCounts& c) {
  const std::vector<uint32_t> id = positionIds(s.vertices);
  std::vector<std::pair<FaceKey, uint32_t>> keys;  // (key, face index) of the faces of non-zero area
  std::vector<bool> skip(s.faces.size(), false);
  for (size_t i = 0; i < s.faces.size(); ++i) {
    const Face& f = s.faces[i];
    if (hasZeroArea(s, f)) {
      skip[i] = true;
      ++c.zeroArea;
      continue;
    }
    FaceKey key{};
    for (int r = 0; r < f.count; ++r) {  // the smallest of the cyclic rotations
      FaceKey k{};
      k[4] = f.count;
      for (int j = 0; j < f.count; ++j) k[j] = id[f.v[(r + j) % f.count]];
      if (r == 0 || k < key) key = k;
    }
    keys.emplace_back(key, uint32_t(i));
  }
  tbb::parallel_sort(keys.begin(), keys.end());  // equal keys in face order: the first one stays
  for (size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first) {
      skip[keys[i].second] = true;
      ++c.duplicates;
    }
  std::vector<Face> kept;
  std::vector<Vec2> keptUv;
  std::vector<Vec3> keptNormals, keptTangents, keptBitangents;
  kept.reserve(s.faces.size());
  for (size_t i = 0; i < s.faces.size(); ++i)
    if (!skip[i]) {
      kept.push_back(s.faces[i]);
      if (s.hasUv()) keptUv.insert(keptUv.end(), s.uv.begin() + long(4 * i), s.uv.begin() + long(4 * i + 4));
      if (s.hasNormals())
        keptNormals.insert(keptNormals.end(), s.normals.begin() + long(4 * i), s.normals.begin() + long(4 * i + 4));
      if (s.hasTangents()) {  // glTF TANGENT
        keptTangents.insert(keptTangents.end(), s.tangents.begin() + long(4 * i), s.tangents.begin() + long(4 * i + 4));
        keptBitangents.insert(keptBitangents.end(), s.bitangents.begin() + long(4 * i),
                              s.bitangents.begin() + long(4 * i + 4));
      }
    }
  c.faces += s.faces.size();
  s.faces = std::move(kept);
  if (s.hasUv()) s.uv = std::move(keptUv);
  if (s.hasNormals()) s.normals = std::move(keptNormals);
  if (s.hasTangents()) s.tangents = std::move(keptTangents), s.bitangents = std::move(keptBitangents);
}

/// "scene.json: skipped 155 of 262661 triangles of Mesh353.obj (150 zero-area, 5 duplicates)[; dropped …]".
std::string line(const std::string& sceneFile, const FileCounts& c) {
  const bool ownFile = c.source.empty() || c.source == sceneFile;
  std::string s = sceneFile + ": skipped " + std::to_string(c.zeroArea + c.duplicates) + " of " +
                  std::to_string(c.faces) + (c.source.empty() ? " faces" : " triangles") +
                  (ownFile ? "" : " of " + c.source) + " (" + std::to_string(c.zeroArea) + " zero-area, " +
                  std::to_string(c.duplicates) + " duplicates)";
  if (c.dropped.empty()) return s;
  constexpr size_t kNamed = 3;
  s += "; dropped " + std::to_string(c.dropped.size()) + (c.dropped.size() == 1 ? " shape" : " shapes") +
       " with no face left (";
  for (size_t i = 0; i < std::min(kNamed, c.dropped.size()); ++i) s += (i ? ", " : "") + c.dropped[i];
  return s + (c.dropped.size() > kNamed ? ", …)" : ")");
}

}  // namespace

bool hasZeroArea(const ShapeDesc& s, const Face& f) {
  double longest = 0;
  for (int i = 0; i < f.count; ++i)
    longest = std::max(longest, glm::length(s.vertices[f.v[(i + 1) % f.count]] - s.vertices[f.v[i]]));
  return !(longest > 0) || !(shapes::faceArea(s, f) > 1e-10 * longest * longest);
}

std::vector<std::string> skipDegenerateFaces(SceneDesc& scene) {
  std::vector<FileCounts> files;  // in the order of first appearance
  std::vector<int> newIndex(scene.shapes.size(), -1);
  std::vector<ShapeDesc> kept;
  kept.reserve(scene.shapes.size());
  for (size_t i = 0; i < scene.shapes.size(); ++i) {
    ShapeDesc& s = scene.shapes[i];
    if (!malformed(s)) {
      auto it = std::find_if(files.begin(), files.end(), [&](const FileCounts& c) { return c.source == s.sourceFile; });
      if (it == files.end()) it = files.insert(files.end(), FileCounts{s.sourceFile});
      skipFaces(s, *it);
      if (s.faces.empty()) {
        it->dropped.push_back(s.name);
        continue;
      }
    }
    newIndex[i] = int(kept.size());
    kept.push_back(std::move(s));
  }
  if (kept.empty() && !scene.shapes.empty())
    throw InputError(scene.file, "shapes", "every face of every shape is zero-area or a duplicate");
  scene.shapes = std::move(kept);
  std::erase_if(scene.lights, [&](LightDesc& l) {
    if (l.type != LightType::Area || l.shape < 0 || size_t(l.shape) >= newIndex.size()) return false;
    l.shape = newIndex[l.shape];
    return l.shape < 0;
  });
  std::vector<std::string> lines;
  for (const FileCounts& c : files) {
    if (c.zeroArea + c.duplicates == 0) continue;
    lines.push_back(line(scene.file, c));
    std::fprintf(stderr, "%s\n", lines.back().c_str());
  }
  return lines;
}

}  // namespace firstshot
