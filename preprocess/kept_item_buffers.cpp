// Item buffers kept between shooting passes (preprocess/kept_item_buffers.h).
#include "preprocess/kept_item_buffers.h"

#include <algorithm>
#include <cassert>

#include "preprocess/adaptive_mesh.h"
#include "preprocess/item_buffer.h"

namespace firstshot {

namespace {

/// A split patch's dividing lines seen from one view: the side of line k on which the ray of the
/// pixel centred at image-plane (u, v) meets the parent's plane is the sign of
/// c[k][0] + u·c[k][1] + v·c[k][2], positive on the side of the line's reference vertex.
struct PixelLines {
  int count;
  double c[3][3] = {};

  PixelLines(const View& view, const AdaptiveMesh::SplitLines& l) : count(l.count) {
    const bool perspective = view.projection == Projection::Perspective;
    for (int k = 0; k < l.count; ++k) {
      // The plane through the line and the rays that meet it: through the eye (perspective), or
      // along the view axis (orthographic). Its side of a point x of the parent's plane is its
      // side of the line within that plane.
      const Vec3d n = perspective ? glm::cross(l.a[k] - view.eye, l.b[k] - view.eye)
                                  : glm::cross(l.b[k] - l.a[k], view.forward);
      const Vec3d origin = perspective ? view.eye : l.a[k];
      // Perspective: the ray eye + t·(forward + u·right + v·up), t > 0. Orthographic: from
      // eye + u·right + v·up along forward, which n is perpendicular to.
      double c0 = perspective ? glm::dot(n, view.forward) : glm::dot(n, view.eye - l.a[k]);
      double c1 = glm::dot(n, view.right), c2 = glm::dot(n, view.up);
      if (glm::dot(n, l.ref[k] - origin) < 0) c0 = -c0, c1 = -c1, c2 = -c2;
      c[k][0] = c0, c[k][1] = c1, c[k][2] = c2;
    }
  }

  int child(double u, double v) const {
    unsigned inside = 0;
    for (int k = 0; k < count; ++k)
      if (c[k][0] + u * c[k][1] + v * c[k][2] > 0) inside |= 1u << k;
    return AdaptiveMesh::childOf(count, inside);
  }
};

}  // namespace

bool KeptItemBuffers::keep(const std::vector<View>& views, const std::vector<std::vector<uint32_t>>& ids, double near,
                           size_t maxBytes) {
  clear();
  views_.resize(views.size());
  size_t total = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    Buffer& b = views_[v];
    b.width = views[v].width, b.height = views[v].height;
    b.rowStart.reserve(size_t(b.height) + 1);
    b.rowStart.push_back(0);
    const uint32_t* row = ids[v].data();
    for (int j = 0; j < b.height; ++j, row += b.width) {
      for (int i = 0; i < b.width;) {
        int e = i + 1;
        while (e < b.width && row[e] == row[i]) ++e;
        b.runs.push_back({row[i], uint32_t(e)});
        i = e;
      }
      b.rowStart.push_back(uint32_t(b.runs.size()));
    }
    total += bytesOf(b);
    if (total > maxBytes) {
      clear();
      return false;
    }
  }
  near_ = near;
  level_ = 0;
  return true;
}

void KeptItemBuffers::followSplit(const std::vector<View>& views, const PatchMesh& mesh,
                                  const std::vector<uint32_t>& first) {
  assert(views.size() == views_.size());
  std::vector<Run> runs;
  for (size_t v = 0; v < views_.size(); ++v) {
    Buffer& b = views_[v];
    const View& view = views[v];
    runs.clear();
    runs.reserve(b.runs.size() + b.runs.size() / 4);
    auto push = [&](size_t rowBegin, uint32_t id, uint32_t end) {
      if (runs.size() > rowBegin && runs.back().id == id)
        runs.back().end = end;
      else
        runs.push_back({id, end});
    };
    const double du = (view.planeMax.x - view.planeMin.x) / view.width;
    for (int j = 0; j < b.height; ++j) {
      const size_t rowBegin = runs.size();
      const double vc = view.pixelCentre(0, j).y;
      uint32_t start = 0;
      for (uint32_t r = b.rowStart[size_t(j)]; r < b.rowStart[size_t(j) + 1]; ++r) {
        const Run run = b.runs[r];
        if (run.id == kNoPatch || first[run.id + 1] - first[run.id] == 1) {
          push(rowBegin, run.id == kNoPatch ? kNoPatch : first[run.id], run.end);
        } else {
          const uint32_t c0 = first[run.id];
          const PixelLines lines(view, AdaptiveMesh::splitLines(&mesh.patches[c0]));
          for (uint32_t i = start; i < run.end; ++i)
            push(rowBegin, c0 + uint32_t(lines.child(view.planeMin.x + (i + 0.5) * du, vc)), i + 1);
        }
        start = run.end;
      }
      b.rowStart[size_t(j)] = uint32_t(rowBegin);
    }
    b.rowStart[size_t(b.height)] = uint32_t(runs.size());
    b.runs.swap(runs);
  }
  ++level_;
}

void KeptItemBuffers::unpack(std::vector<std::vector<uint32_t>>& ids) const {
  ids.resize(views_.size());
  for (size_t v = 0; v < views_.size(); ++v) {
    ids[v].resize(size_t(views_[v].width) * size_t(views_[v].height));
    uint32_t* out = ids[v].data();
    forEachRun(v, [&](uint32_t id, size_t begin, size_t end) { std::fill(out + begin, out + end, id); });
  }
}

size_t KeptItemBuffers::bytesOf(const Buffer& b) {
  return b.runs.size() * sizeof(Run) + b.rowStart.size() * sizeof(uint32_t);
}

size_t KeptItemBuffers::bytes() const {
  size_t total = 0;
  for (const Buffer& b : views_) total += bytesOf(b);
  return total;
}

void KeptItemBuffers::clear() {
  views_.clear();
  views_.shrink_to_fit();
  near_ = 0;
  level_ = 0;
}

}  // namespace firstshot
