// Packed patches: a vertex pool, runs of (shape, material), per-patch geometry (firstshot_patches.h).
#include "common/table/firstshot_patches.h"

#include <array>
#include <bit>
#include <cstring>
#include <unordered_map>

#include "common/util/hash.h"

namespace firstshot {

namespace {

/// A corner by its bit pattern: -0 and +0 (and any two NaNs) stay distinct, so unpacking is exact.
using CornerBits = std::array<uint32_t, 3>;

struct CornerHash {
  size_t operator()(const CornerBits& b) const {
    return size_t(Hasher::mix((uint64_t(b[0]) << 32 | b[1]) ^ Hasher::mix(b[2])));
  }
};

CornerBits bitsOf(const Vec3& v) { return {std::bit_cast<uint32_t>(v.x), std::bit_cast<uint32_t>(v.y), std::bit_cast<uint32_t>(v.z)}; }

}  // namespace

PackedPatches packPatches(const PatchMesh& mesh) {
  PackedPatches out;
  const size_t n = mesh.patches.size();
  out.corners.reserve(n), out.index.reserve(3 * n), out.normal.reserve(n), out.centroid.reserve(n), out.area.reserve(n);
  std::unordered_map<CornerBits, uint32_t, CornerHash> pool;
  pool.reserve(n);
  for (const Patch& p : mesh.patches) {
    if (out.runLength.empty() || out.runShape.back() != p.shape || out.runMaterial.back() != p.material) {
      out.runShape.push_back(p.shape), out.runMaterial.push_back(p.material), out.runLength.push_back(0);
    }
    ++out.runLength.back();
    out.corners.push_back(uint8_t(p.count));
    for (uint32_t k = 0; k < p.count; ++k) {
      const auto [it, added] = pool.try_emplace(bitsOf(p.v[k]), uint32_t(out.vertices.size()));
      if (added) out.vertices.push_back(p.v[k]);
      out.index.push_back(it->second);
    }
    out.normal.push_back(p.normal), out.centroid.push_back(p.centroid), out.area.push_back(p.area);
  }
  return out;
}

void unpackPatches(const PackedPatches& p, PatchMesh& mesh, const std::function<void(const std::string&)>& fail) {
  const size_t n = p.corners.size();
  if (p.normal.size() != n || p.centroid.size() != n || p.area.size() != n)
    fail("per-patch arrays of different lengths (corrupt file)");
  if (p.runShape.size() != p.runLength.size() || p.runMaterial.size() != p.runLength.size())
    fail("run arrays of different lengths (corrupt file)");
  uint64_t inRuns = 0, cornerSum = 0;
  for (uint32_t len : p.runLength) {
    if (len == 0) fail("an empty run of patches (corrupt file)");
    inRuns += len;
  }
  if (inRuns != n) fail("runs do not add up to the patch count (corrupt file)");
  for (uint8_t c : p.corners) {
    if (c != 3 && c != 4) fail("a patch with " + std::to_string(c) + " corners (corrupt file)");
    cornerSum += c;
  }
  if (cornerSum != p.index.size()) fail("corner counts do not add up to the corner indices (corrupt file)");
  for (uint32_t i : p.index)
    if (i >= p.vertices.size()) fail("a corner index outside the vertex pool (corrupt file)");
  mesh.patches.resize(n);
  size_t j = 0, k = 0;
  for (size_t r = 0; r < p.runLength.size(); ++r) {
    for (uint32_t m = 0; m < p.runLength[r]; ++m, ++j) {
      Patch& q = mesh.patches[j];
      q.count = p.corners[j], q.shape = p.runShape[r], q.material = p.runMaterial[r];
      for (uint32_t c = 0; c < q.count; ++c) q.v[c] = p.vertices[p.index[k++]];
      if (q.count == 3) q.v[3] = q.v[2];
      q.normal = p.normal[j], q.centroid = p.centroid[j], q.area = p.area[j];
      if (!(q.area > 0)) fail("patch " + std::to_string(j) + " has no positive area (corrupt file)");
    }
  }
}

}  // namespace firstshot
