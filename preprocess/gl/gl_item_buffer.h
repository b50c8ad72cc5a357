#pragma once
/// @file gl_item_buffer.h
/// The OpenGL item-buffer back end: rasterises the geometry into a GL_R32UI colour target with a
/// 32-bit float depth buffer and REVERSED Z (glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), depth cleared
/// to 0, GL_GREATER): no blending, no multisampling, no dithering, no culling.
///
/// Exactness: the patch ID is a flat uint vertex attribute (glVertexAttribIPointer), written unchanged
/// to the integer target and read back with glReadPixels(GL_RED_INTEGER, GL_UNSIGNED_INT): all 32 bits,
/// never through a float. Geometry stays in world space on the GPU; the vertex shader subtracts the eye
/// given as a float pair (hi + lo = eye to ~1e-14 relative) before anything else, so the camera-relative
/// position has float precision relative to its distance from the eye: a patch 1e-4 m from an eye at
/// 10 m coordinates still rasterises correctly.
///
/// Speed: triangles are sorted along a Morton curve at upload and grouped into clusters of 128; each
/// render draws only the clusters whose bounding sphere meets the view frustum (glMultiDrawArrays).
/// The order of triangles only matters between coplanar overlapping triangles (exact depth ties).
///
/// Alpha cut-outs: a scene with them draws with preprocess/gl/gl_cutouts.h's shaders, which discard the
/// fragments where a cut-out surface is absent.
#include <cstdint>
#include <memory>
#include <vector>

#include "preprocess/gl/gl_context.h"
#include "preprocess/gl/gl_cutouts.h"
#include "preprocess/item_buffer.h"

namespace firstshot {

class GLItemBuffer final : public ItemBufferRenderer {
 public:
  /// Creates its own context (current on the calling thread) and uploads the geometry once.
  /// @param sceneBounds  for the near plane (@p nearRelative × diagonal) and the far plane
  /// @throws std::runtime_error if the back end is unavailable or OpenGL fails
  GLItemBuffer(const ItemGeometry& geometry, const Bounds3d& sceneBounds, GLBackend backend = GLBackend::OSMesa,
               double nearRelative = 1e-6);
  GLItemBuffer(const PatchMesh& mesh, const Bounds3d& sceneBounds, GLBackend backend = GLBackend::OSMesa,
               double nearRelative = 1e-6);
  ~GLItemBuffer() override;
  GLItemBuffer(const GLItemBuffer&) = delete;
  GLItemBuffer& operator=(const GLItemBuffer&) = delete;

  /// Makes the context current on the calling thread if needed, renders and reads back.
  void render(const View& view, std::vector<uint32_t>& ids) override;
  const char* name() const override;
  double nearPlane() const override { return near_; }
  GLContext& context() { return context_; }
  /// Whether the geometry has alpha cut-outs (their fragments are discarded where the surface is absent).
  bool hasCutouts() const { return cutouts_ != nullptr; }

  // ---- Item buffers kept in GPU memory (reduced there: preprocess/gl/gl_reduce.h) ----
  /// Renders @p view into the GL_R32UI texture of slot @p slot (0, 1, …: one per view of a window,
  /// resized to the view), texel (i, j) = pixel (i, j), and returns the texture; nothing is read back.
  unsigned int renderToTexture(const View& view, int slot);
  /// Reads slot @p slot's texture back into @p ids (row-major, as render() writes it).
  void readTexture(int slot, std::vector<uint32_t>& ids);

 private:
  /// Draws @p view into @p texture (0: the renderbuffer render() reads back); false if nothing was
  /// drawn and the target not touched (render() then leaves ids at kNoPatch).
  bool draw(const View& view, unsigned int texture);
  void ensureFramebuffer(int width, int height);
  void checkErrors(const char* where);

  GLContext context_;
  Bounds3d bounds_;
  double near_ = 0;
  unsigned int program_ = 0, vao_ = 0, vbo_ = 0;
  unsigned int fbo_ = 0, colour_ = 0, depth_ = 0;
  int fbWidth_ = 0, fbHeight_ = 0;
  int64_t vertexCount_ = 0;
  /// Clusters of consecutive triangles (Morton-sorted at upload), culled per view against its frustum.
  struct Cluster {
    Vec3d centre;
    double radius;
    int first, count;  ///< vertex range
  };
  std::vector<Cluster> clusters_;
  std::vector<int> drawFirst_, drawCount_;  // scratch for glMultiDrawArrays
  int locEyeHi_ = -1, locEyeLo_ = -1, locRight_ = -1, locUp_ = -1, locForward_ = -1;
  int locPlane_ = -1, locDepth_ = -1, locOrtho_ = -1;
  std::unique_ptr<GLCutouts> cutouts_;  ///< alpha cut-outs; null in a scene without them
  struct Slot {
    unsigned int texture = 0;
    int width = 0, height = 0;
  };
  std::vector<Slot> slots_;  ///< renderToTexture's targets
};

}  // namespace firstshot
