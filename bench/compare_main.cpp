// firstshot-compare: the error of a rendered image against a reference (bench/image_metrics.h),
// printed as one JSON object; or the mean of two images (a reference from two half-sample renders).
//   firstshot-compare TEST.exr REF.exr [--epsilon-fraction F]
//   firstshot-compare --mean A.exr B.exr -o OUT.exr
#include <CLI/CLI.hpp>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <string>
#include <vector>

#include "bench/image_metrics.h"
#include "common/util/cli.h"
#include "common/util/error.h"

namespace {

using namespace firstshot;

struct RGBImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< interleaved, 3 channels
};

/// Reads the first three channels of an image (one channel is repeated into all three).
RGBImage readRGB(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw InputError(path, "image", "cannot open: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  const int nc = spec.nchannels;
  if (nc < 1 || spec.width <= 0 || spec.height <= 0) throw InputError(path, "image", "empty image");
  std::vector<float> all(size_t(spec.width) * spec.height * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, all.data()))
    throw InputError(path, "image", "cannot read pixels: " + in->geterror());
  RGBImage img{spec.width, spec.height, std::vector<float>(size_t(spec.width) * spec.height * 3)};
  for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
    for (int c = 0; c < 3; ++c) img.rgb[3 * p + c] = all[p * nc + (nc >= 3 ? c : 0)];
  return img;
}

void checkSameSize(const RGBImage& a, const RGBImage& b, const std::string& pathB) {
  if (a.width != b.width || a.height != b.height)
    throw InputError(pathB, "image", "size " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                                         " differs from " + std::to_string(a.width) + "x" + std::to_string(a.height));
}

void writeRGB(const std::string& path, const RGBImage& img) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error("cannot create " + path + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(img.width, img.height, 3, OIIO::TypeDesc::FLOAT);
  spec.attribute("Software", "firstshot-compare");
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, img.rgb.data()) || !out->close())
    throw std::runtime_error("cannot write " + path + ": " + out->geterror());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"firstshot-compare: error of an image against a reference (JSON on stdout), or the mean of two images"};
  std::vector<std::string> images;
  double epsFraction = 0.01;
  bool mean = false;
  std::string output;
  app.add_option("images", images, "TEST REF (or A B with --mean)")->required()->expected(2);
  app.add_option("--epsilon-fraction", epsFraction, "ε = this × mean(REF) in the relative errors")->check(CLI::NonNegativeNumber);
  app.add_flag("--mean", mean, "write the mean of the two images to -o instead of comparing");
  app.add_option("-o,--output", output, "output image of --mean (.exr)");
  CLI11_PARSE(app, argc, argv);
  return runTool("firstshot-compare", [&] {
    const RGBImage a = readRGB(images[0]);
    const RGBImage b = readRGB(images[1]);
    checkSameSize(a, b, images[1]);
    if (mean) {
      if (output.empty()) throw InputError("", "-o", "--mean needs an output file");
      writeRGB(output, RGBImage{a.width, a.height, bench::meanImage(a.rgb, b.rgb)});
      return 0;
    }
    const bench::ImageErrors e = bench::compareImages(a.rgb, b.rgb, epsFraction);
    std::printf(
        "{\"rel_rmse\": %.9g, \"mare\": %.9g, \"nrmse\": %.9g, \"rmse\": %.9g, \"mean_ref\": %.9g, \"epsilon\": %.9g, "
        "\"values\": %zu, \"non_finite\": %zu, \"width\": %d, \"height\": %d}\n",
        e.relRmse, e.mare, e.nrmse, e.rmse, e.meanRef, e.epsilon, e.values, e.nonFinite, a.width, a.height);
    return 0;
  });
}
