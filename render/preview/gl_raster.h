#pragma once
/// @file gl_raster.h
/// Everything the preview draws with OpenGL (3.3 core; a context must be current):
///  - the instant picture: the RasterMesh rasterised into an offscreen target of the image's size
///    (linear radiance, RGBA32F, plus a depth texture), with the renderer's pinhole camera;
///  - the display: the progressive film or the instant picture, scaled by 2^exposure, clamped,
///    sRGB-encoded, letterboxed into the window (1:1 when the sizes match);
///  - overlays: patch edges and irradiance-cache records as lines, hidden where the instant
///    picture's depth says they are occluded.
#include <cstdint>
#include <memory>
#include <vector>

#include "common/scene/scene_desc.h"
#include "render/preview/raster_mesh.h"

namespace firstshot {

struct DisplaySettings {
  bool showFilm = false;     ///< the film (uploadFilm) instead of the instant picture
  float exposure = 0.0f;     ///< stops: radiance is scaled by 2^exposure
  bool edges = false;        ///< patch outlines
  bool records = false;      ///< irradiance-cache records (setRecords)
};

class GLRaster {
 public:
  /// Compiles the shaders. @throws std::runtime_error with the compiler's log on failure.
  GLRaster();
  ~GLRaster();
  GLRaster(const GLRaster&) = delete;
  GLRaster& operator=(const GLRaster&) = delete;

  /// Uploads the triangles and edge lines of @p mesh.
  void setMesh(const RasterMesh& mesh);
  /// Uploads record circles (line segments, two points each).
  void setRecords(const std::vector<Vec3>& lines);
  /// Rasterises the mesh with @p camera into the offscreen target (camera.width × camera.height).
  void renderInstant(const CameraDesc& camera);
  /// Uploads a film image: linear RGB, width·height·3 floats, top row first.
  void uploadFilm(const std::vector<float>& rgb, int width, int height);
  /// Draws into the default framebuffer (@p fbWidth × @p fbHeight pixels).
  void display(int fbWidth, int fbHeight, const DisplaySettings& settings);

  /// The instant picture's linear radiance, width·height·3 floats, top row first.
  std::vector<float> readInstant(int& width, int& height) const;
  /// The displayed image as 8-bit RGB (the letterboxed region of the back buffer, before the swap),
  /// top row first.
  std::vector<uint8_t> readDisplay(int& width, int& height) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace firstshot
