#pragma once
/// @file vertex_welder.h
/// Joining mesh vertices at bit-identical positions, so that triangles sharing an edge share its vertices (the
/// meshes of asset files, common/formats/assets/mesh_import.cpp, and of Mitsuba's serialized files, common/formats/mitsuba/mitsuba_serialized.cpp).
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/util/hash.h"
#include "common/util/math.h"

namespace firstshot {

/// Appends positions to a vertex list, each distinct position once, in the order they are first seen.
class Welder {
 public:
  explicit Welder(std::vector<Vec3d>& vertices) : vertices_(vertices) {}
  /// The index of @p p in the list, appended if it is new (−0 and +0 are one position).
  uint32_t index(Vec3d p) {
    p += Vec3d(0.0);  // -0 -> +0
    auto [it, inserted] = map_.try_emplace(p, uint32_t(vertices_.size()));
    if (inserted) vertices_.push_back(p);
    return it->second;
  }

 private:
  struct KeyHash {
    size_t operator()(const Vec3d& p) const { return size_t(Hasher().add(p).value()); }
  };
  std::vector<Vec3d>& vertices_;
  std::unordered_map<Vec3d, uint32_t, KeyHash> map_;
};

}  // namespace firstshot
