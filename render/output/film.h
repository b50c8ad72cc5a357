#pragma once
/// @file film.h
/// Per-pixel accumulation of radiance samples (with the sums of squares, for error estimates) and
/// of the AOVs, and image output through OpenImageIO: EXR (linear float RGB, optional albedo and
/// normal layers for external denoisers) and PNG (exposure, clamp, sRGB transfer curve, 8 bits).
#include <cstdint>
#include <string>
#include <vector>

#include "common/util/math.h"

namespace firstshot {

class Film {
 public:
  /// @throws InputError if a size is below 1 or the film (100 bytes a pixel) cannot fit in physical
  /// memory (common/util/memory_limit.h), before anything is allocated.
  Film(int width, int height);

  /// @throws InputError naming @p file (the scene) and "image size" if a film of @p width × @p height
  /// pixels cannot be made (a size below 1, or 100 bytes a pixel more than the physical memory).
  static void requireFits(int width, int height, const std::string& file = "");

  int width() const { return width_; }
  int height() const { return height_; }

  /// Adds one sample to pixel (x, y). Not synchronised: each pixel must be written by one thread
  /// at a time, and in a fixed order for reproducible sums.
  void add(int x, int y, const Color& L, const Color& albedo, const Vec3& normal) {
    const size_t i = index(x, y);
    const Vec3d l(L);
    s_.sum[i] += l;
    s_.sumSq[i] += l * l;
    s_.albedo[i] += Vec3d(albedo);
    s_.normal[i] += Vec3d(normal);
    ++s_.count[i];
  }

  /// The raw per-pixel accumulators, exactly as add() sums them (row-major, width·height each).
  struct Sums {
    std::vector<Vec3d> sum, sumSq, albedo, normal;  ///< Σ L, Σ L², Σ albedo, Σ normal
    std::vector<uint32_t> count;                    ///< samples added
  };
  /// For checkpoints (render/loop/checkpoint.h): restoring the sums with setSums() and adding the
  /// remaining samples in order gives the same film, bit for bit, as an uninterrupted render.
  const Sums& sums() const { return s_; }
  /// @throws std::invalid_argument if a vector's size is not width·height.
  void setSums(Sums sums);
  /// One pixel's accumulators, for moving pixels between the films of MPI ranks (render/output/film_exchange.h).
  struct PixelSums {
    Vec3d sum, sumSq, albedo, normal;
    uint32_t count;
  };
  PixelSums pixelSums(int x, int y) const {
    const size_t i = index(x, y);
    return {s_.sum[i], s_.sumSq[i], s_.albedo[i], s_.normal[i], s_.count[i]};
  }
  void setPixelSums(int x, int y, const PixelSums& p) {
    const size_t i = index(x, y);
    s_.sum[i] = p.sum, s_.sumSq[i] = p.sumSq, s_.albedo[i] = p.albedo, s_.normal[i] = p.normal, s_.count[i] = p.count;
  }

  /// Mean radiance of pixel (x, y) (0 with no sample).
  Vec3d mean(int x, int y) const;
  /// Unbiased sample variance of pixel (x, y)'s samples, per channel (0 with fewer than 2).
  Vec3d variance(int x, int y) const;
  uint32_t samples(int x, int y) const { return s_.count[index(x, y)]; }
  /// Mean first-hit albedo and (renormalised) normal of pixel (x, y).
  Vec3d albedo(int x, int y) const;
  Vec3d normal(int x, int y) const;

  /// Writes the image; the format follows the extension of @p path: .exr (float; with @p aov also
  /// the layers albedo.{R,G,B} and normal.{X,Y,Z}) or .png (8-bit sRGB after scaling by
  /// 2^@p exposure). With @p efficacy > 0 (lm/W) an EXR holds, instead of R, G, B, one channel Y:
  /// the luminance in cd/m² (luminance(efficacy)); a PNG is unaffected. Written atomically
  /// (temporary file, then rename).
  /// @throws InputError for an unsupported extension, std::runtime_error for I/O failures.
  void write(const std::string& path, bool aov, float exposure = 0.0f, double efficacy = 0.0) const;

  /// Luminance of every pixel in cd/m²: @p efficacy (lm/W) · Y(mean radiance), Y with the Rec. 709
  /// weights (common/lights/photometry.h); row-major, width·height values.
  std::vector<double> luminance(double efficacy) const;

  /// Reads an image written by write() (OpenEXR or PNG; render/output/image_io.h) into floats, width·height·channels
  /// values; @p channelNames receives the channel names (R, G, B first). For tests and tools.
  static std::vector<float> read(const std::string& path, int& width, int& height, std::vector<std::string>& channelNames);

 private:
  size_t index(int x, int y) const { return size_t(y) * size_t(width_) + size_t(x); }
  void writeExr(const std::string& path, bool aov, double efficacy) const;
  void writePng(const std::string& path, float exposure) const;

  int width_, height_;
  Sums s_;
};

/// sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1].
float linearToSrgb(float v);

}  // namespace firstshot
