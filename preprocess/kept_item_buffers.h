#pragma once
/// @file kept_item_buffers.h
/// A light sample's item buffers kept from the first shooting pass for the refinement passes
/// (preprocess/preprocessor.cpp). When a patch is split, the pixels that showed it are handed to its
/// children by the side of the parent's dividing lines on which the pixel's ray meets the parent's
/// plane, so that a refinement pass re-reads the buffers instead of re-tracing the pixels around
/// the split patches. Stored row by row as runs of one patch (the coarse mesh's patches cover long
/// runs), so they take a fraction of the 4 bytes a pixel of the buffers themselves.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/patches/patches.h"
#include "preprocess/view.h"

namespace firstshot {

class KeptItemBuffers {
 public:
  /// Keeps @p ids (one buffer per view of @p views, as ItemBufferRenderer::render gives them,
  /// rendered with near plane @p near, m) as the buffers of refinement level 0. Returns false, and
  /// keeps nothing, if they would take more than @p maxBytes.
  bool keep(const std::vector<View>& views, const std::vector<std::vector<uint32_t>>& ids, double near,
            size_t maxBytes);

  /// Whether buffers are kept, and over the mesh of refinement level @p level.
  bool at(int level) const { return !views_.empty() && level_ == level; }

  /// Brings the buffers from the mesh before a split to @p mesh, the mesh after it (and to the next
  /// level); @p first as AdaptiveMesh::split() returns it, @p views those the buffers were kept
  /// from. A pixel of an unsplit patch j now shows first[j]; a pixel of a split patch, the child
  /// on whose part of the parent's plane the pixel's ray meets it.
  void followSplit(const std::vector<View>& views, const PatchMesh& mesh, const std::vector<uint32_t>& first);

  /// The buffers, one patch ID (or kNoPatch) per pixel and view.
  void unpack(std::vector<std::vector<uint32_t>>& ids) const;

  /// Calls @p f(id, begin, end) for every run of view @p view: pixels [begin, end) in row-major
  /// order show patch id (or kNoPatch).
  template <class F>
  void forEachRun(size_t view, F&& f) const {
    const Buffer& b = views_[view];
    size_t rowOffset = 0;
    for (int j = 0; j < b.height; ++j, rowOffset += size_t(b.width)) {
      uint32_t start = 0;
      for (uint32_t r = b.rowStart[size_t(j)]; r < b.rowStart[size_t(j) + 1]; ++r) {
        f(b.runs[r].id, rowOffset + start, rowOffset + b.runs[r].end);
        start = b.runs[r].end;
      }
    }
  }

  /// The near plane the buffers were rendered with, m (depth along the view's forward axis).
  double nearPlane() const { return near_; }
  /// Memory the runs take, bytes.
  size_t bytes() const;
  void clear();

 private:
  struct Run {
    uint32_t id;   ///< patch, or kNoPatch
    uint32_t end;  ///< the run ends before this column
  };
  struct Buffer {
    int width = 0, height = 0;
    std::vector<uint32_t> rowStart;  ///< height + 1 offsets into runs
    std::vector<Run> runs;
  };
  static size_t bytesOf(const Buffer& b);

  std::vector<Buffer> views_;
  double near_ = 0;
  int level_ = 0;
};

}  // namespace firstshot
