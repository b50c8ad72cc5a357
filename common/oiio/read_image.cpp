// The OpenImageIO module: one function, loaded on demand by common/materials/texture.cpp (common/oiio/read_image.h).
#include "common/oiio/read_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <memory>

extern "C" __attribute__((visibility("default"))) void firstshot_read_image(const char* name, const void* bytes,
                                                                            size_t size, firstshot::ModuleImage* out) {
  using namespace OIIO;
  std::unique_ptr<Filesystem::IOMemReader> memory;
  if (bytes) memory = std::make_unique<Filesystem::IOMemReader>(bytes, size);
  auto in = ImageInput::open(name, nullptr, memory.get());
  if (!in) {
    out->error = OIIO::geterror();
    if (out->error.empty()) out->error = "cannot open";
    return;
  }
  const ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
    out->error = "not a 2D image";
    return;
  }
  out->width = spec.width;
  out->height = spec.height;
  out->channels = spec.nchannels;
  out->integer = !spec.format.is_floating_point();
  out->pixels.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, out->pixels.data())) {
    out->error = in->geterror();
    if (out->error.empty()) out->error = "cannot decode";
    out->pixels.clear();
  }
}
