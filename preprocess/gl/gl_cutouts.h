#pragma once
/// @file gl_cutouts.h
/// Alpha cut-outs in the GL item buffer: the fragments of a cut-out patch are discarded where its
/// surface is absent, as the Embree back end's filter rejects such hits (common/patches/patch_cutouts.h), so that the item
/// buffer shows what lies behind a hole.
///
/// Each vertex of a cut-out patch's triangle carries its texture coordinates, the alpha texture's transform already
/// applied (the transform is affine and so is the map from a patch triangle to its face's texture coordinates, so
/// interpolating the corners is exact), and a slot: one per (material, with or without texture coordinates). The
/// fragment shader repeats Texture::alphaLookup (bilinear or nearest on level 0, texel centres at (i + ½)/w, the wrap
/// modes) from the alpha texels in a shader storage buffer, in single precision: a texel boundary or the cut-off may fall
/// a float's rounding away from where the CPU puts it. Mask: the fragment stays where alpha ≥ the cut-off. Blend:
/// it stays with probability alpha, by a hash of the pixel, the patch and the view (the same view gives the same
/// item buffer on every thread). Opaque patches carry slot 0 and never run the lookup.
///
/// A scene without cut-outs uses none of this: the item buffer's programs and outputs are those of before.
#include <cstdint>
#include <string>
#include <vector>

#include "preprocess/item_buffer.h"
#include "preprocess/view.h"

namespace firstshot {

class GLCutouts {
 public:
  /// Per-vertex data and slots of @p geometry (whose cutouts must be set), its triangles taken in @p order; uploads
  /// the vertex buffer and the two storage buffers. Needs the item buffer's context current.
  GLCutouts(const ItemGeometry& geometry, const std::vector<uint32_t>& order);
  ~GLCutouts() = default;  ///< leaves the buffers to the context (destroy() frees them while it is current)
  GLCutouts(const GLCutouts&) = delete;
  GLCutouts& operator=(const GLCutouts&) = delete;

  /// Deletes the buffers; the context must be current.
  void destroy();
  /// Adds attributes 2 (texture coordinates) and 3 (slot) to vertex array @p vao, from buffer binding 1.
  void attach(unsigned int vao) const;
  /// Binds the storage buffers and sets the blend coin's seed for @p view in @p program (current).
  void bind(unsigned int program, const View& view) const;

  /// The preamble that makes the item buffer's vertex shader pass the attributes on.
  static const char* vertexDefines();
  /// The fragment shader that discards absent fragments.
  static const char* fragmentShader();

 private:
  unsigned int vbo_ = 0, params_ = 0, texels_ = 0;
};

}  // namespace firstshot
