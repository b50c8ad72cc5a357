// Image files through OpenEXR and libpng (render/output/image_io.h).
#include "render/output/image_io.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "common/util/atomic_file.h"
#include "common/util/error.h"

namespace firstshot::image {

namespace {

constexpr const char* kSoftware = "firstshot-render";

/// The order read() reports an EXR's channels in: colour first, the AOVs after (EXR stores names sorted).
int channelRank(const std::string& name) {
  static const std::array<const char*, 5> first = {"R", "G", "B", "A", "Y"};
  for (size_t i = 0; i < first.size(); ++i)
    if (name == first[i]) return int(i);
  return int(first.size());
}

Image readExr(const std::string& path) {
  Imf::InputFile file(path.c_str());
  const Imath::Box2i dw = file.header().dataWindow();
  Image im;
  const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
  if (w < 1 || h < 1 || w > (1 << 20) || h > (1 << 20) || w * h > (1L << 28))
    throw InputError(path, "", "unreasonable image size " + std::to_string(w) + " x " + std::to_string(h));
  im.width = int(w), im.height = int(h);
  for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
    im.channels.emplace_back(it.name());
  std::stable_sort(im.channels.begin(), im.channels.end(),
                   [](const std::string& a, const std::string& b) { return channelRank(a) < channelRank(b); });
  const size_t nc = im.channels.size();
  im.data.assign(size_t(w) * size_t(h) * nc, 0.0f);
  Imf::FrameBuffer fb;
  for (size_t c = 0; c < nc; ++c)
    fb.insert(im.channels[c], Imf::Slice::Make(Imf::FLOAT, im.data.data() + c, dw, sizeof(float) * nc,
                                               sizeof(float) * nc * size_t(w)));
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
  return im;
}

Image readPng(const std::string& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    throw InputError(path, "", std::string("cannot read PNG (") + png.message + ")");
  const bool alpha = (png.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  png.format = alpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  std::vector<uint8_t> bytes(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, bytes.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    throw InputError(path, "", "cannot read PNG (" + why + ")");
  }
  Image im;
  im.width = int(png.width), im.height = int(png.height);
  im.channels = alpha ? std::vector<std::string>{"R", "G", "B", "A"} : std::vector<std::string>{"R", "G", "B"};
  im.data.resize(bytes.size());
  std::transform(bytes.begin(), bytes.end(), im.data.begin(), [](uint8_t b) { return float(b) / 255.0f; });
  return im;
}

bool hasPngSignature(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  png_byte sig[8] = {};
  return f.read(reinterpret_cast<char*>(sig), 8) && png_sig_cmp(sig, 0, 8) == 0;
}

}  // namespace

void writeExr(const std::string& path, int width, int height, const std::vector<std::string>& channels,
              const float* data) {
  writeAtomically(path, [&](const std::string& tmp) {
    try {
      Imf::Header header(width, height);
      header.compression() = Imf::ZIP_COMPRESSION;
      header.insert("software", Imf::StringAttribute(kSoftware));
      Imf::FrameBuffer fb;
      const size_t nc = channels.size(), xStride = sizeof(float) * nc, yStride = xStride * size_t(width);
      for (size_t c = 0; c < nc; ++c) {
        header.channels().insert(channels[c], Imf::Channel(Imf::FLOAT));
        // OpenEXR's slices take non-const pointers but only read from them when writing.
        fb.insert(channels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(data + c)), xStride,
                                          yStride));
      }
      Imf::OutputFile file(tmp.c_str(), header);
      file.setFrameBuffer(fb);
      file.writePixels(height);
    } catch (const std::exception& e) {
      throw std::runtime_error(path + ": write failed (" + e.what() + ")");
    }
  });
}

void writePng(const std::string& path, int width, int height, const uint8_t* rgb) {
  writeAtomically(path, [&](const std::string& tmp) {
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = png_uint_32(width), png.height = png_uint_32(height);
    png.format = PNG_FORMAT_RGB;
    if (!png_image_write_to_file(&png, tmp.c_str(), 0, rgb, 0, nullptr))
      throw std::runtime_error(path + ": write failed (" + png.message + ")");
  });
}

Image read(const std::string& path) {
  if (!std::ifstream(path, std::ios::binary)) throw InputError(path, "", "cannot open image");
  if (hasPngSignature(path)) return readPng(path);
  if (!Imf::isOpenExrFile(path.c_str())) throw InputError(path, "", "not an OpenEXR or PNG image");
  try {
    return readExr(path);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, "", std::string("cannot read image (") + e.what() + ")");
  }
}

}  // namespace firstshot::image
