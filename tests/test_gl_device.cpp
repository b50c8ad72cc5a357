// EGL device selection (preprocess/gl/egl_devices.h, --gl-device): EGL lists at least one device here
// (Mesa's software device; on a GPU machine the GPU too), each opens an OpenGL 4.5 context, a device number out of
// range is an input error naming the count, the summary line names the GL_RENDERER the item buffers ran on, and
// --backend auto takes GL on a GPU only. And firstshot-fsd-compare's measure (preprocess/table_compare.h).
#include <gtest/gtest.h>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "preprocess/gl/gl_context.h"
#include "preprocess/preprocessor.h"
#include "preprocess/table_compare.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

const std::string kPreprocess = FIRSTSHOT_PREPROCESS_EXE;
const std::string kPlane = test::source("scenes/point-over-plane.json");

/// GL_RENDERER of an EGL context, or "" (with the reason in @p why) when EGL is unavailable here.
std::string eglRenderer(std::string& why) {
  try {
    return GLContext(GLBackend::EGL).renderer();
  } catch (const std::exception& e) {
    why = e.what();
    return "";
  }
}

TEST(GLDevice, ListsDevicesThatEachOpenAContext) {
  std::string why;
  if (eglRenderer(why).empty()) GTEST_SKIP() << "EGL unavailable here: " << why;
  const std::vector<EglDeviceInfo> devices = listEglDevices();
  ASSERT_GE(devices.size(), 1u) << "EGL made a context but lists no device (EGL_EXT_device_enumeration)";
  for (size_t i = 0; i < devices.size(); ++i) {
    const EglDeviceInfo& d = devices[i];
    EXPECT_EQ(d.index, int(i));
    std::string renderer;
    try {
      renderer = GLContext(GLBackend::EGL, d.index).renderer();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "device " << i << ": " << e.what();
      continue;
    }
    std::printf("EGL device %zu: %s (%s)\n", i, renderer.c_str(), d.software ? "software" : "GPU");
    EXPECT_FALSE(renderer.empty());
    if (d.software) {
      EXPECT_TRUE(isSoftwareRenderer(renderer)) << renderer;  // Mesa's software device is llvmpipe
    }
  }
}

TEST(GLDevice, DeviceOutOfRangeIsAnInputErrorNamingTheCount) {
  const size_t count = listEglDevices().size();
  try {
    setEglDevice(int(count));
    FAIL() << "device " << count << " of " << count << " accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.element(), "--gl-device");
    EXPECT_NE(std::string(e.what()).find("EGL lists " + std::to_string(count) + " device"), std::string::npos) << e.what();
  }
  setEglDevice(kEglDeviceAuto);
  // The tool: exit 2 with the same message; "list" prints the devices and exits 0.
  const auto bad = test::run(kPreprocess + " " + kPlane + " -q -o /dev/null --gl-device " + std::to_string(count));
  EXPECT_EQ(bad.exitCode, kExitBadInput) << bad.output;
  EXPECT_NE(bad.output.find("--gl-device: device " + std::to_string(count) + " does not exist"), std::string::npos) << bad.output;
  const auto notNumber = test::run(kPreprocess + " " + kPlane + " -q -o /dev/null --gl-device first");
  EXPECT_EQ(notNumber.exitCode, kExitBadInput) << notNumber.output;
  const auto osmesa = test::run(kPreprocess + " " + kPlane + " -q -o /dev/null --gl osmesa --gl-device 0");
  EXPECT_EQ(osmesa.exitCode, kExitBadInput) << osmesa.output;
  const auto list = test::run(kPreprocess + " --gl-device list");
  EXPECT_EQ(list.exitCode, 0) << list.output;
  EXPECT_NE(list.output.find("EGL devices (EGL_EXT_device_enumeration): " + std::to_string(count)), std::string::npos) << list.output;
  if (count > 0) {
    EXPECT_NE(list.output.find("  0: "), std::string::npos) << list.output;
  }
}

TEST(GLDevice, SummaryNamesTheRendererTheItemBuffersRanOn) {
  const std::string fsd = test::tempDir() + "/plane.fsd";
  const std::string run = kPreprocess + " " + kPlane + " -q -o " + fsd + " --threads 2 --resolution ";
  const auto osmesa = test::run(run + "32 --backend gl --gl osmesa");
  ASSERT_EQ(osmesa.exitCode, 0) << osmesa.output;
  // (No OSMesa context in this process: after EGL ones, glad's pointers are EGL's, which OSMesa's contexts do not take.)
  const auto m = test::regexSearch(osmesa.output, R"(\[gl/osmesa \((.+)\); R = 32\])");
  ASSERT_FALSE(m.empty()) << osmesa.output;
  EXPECT_TRUE(isSoftwareRenderer(m[1])) << m[1];  // OSMesa is Mesa's CPU rasteriser
  std::string why;
  const std::string renderer = eglRenderer(why);
  if (renderer.empty()) GTEST_SKIP() << "EGL unavailable here: " << why;
  const auto egl = test::run(run + "32 --backend gl --gl egl");
  ASSERT_EQ(egl.exitCode, 0) << egl.output;
  EXPECT_NE(egl.output.find("[gl/egl (" + renderer + "); R = 32]"), std::string::npos) << egl.output;
  const auto device0 = test::run(run + "32 --backend gl --gl-device 0");
  ASSERT_EQ(device0.exitCode, 0) << device0.output;
  EXPECT_NE(device0.output.find("[gl/egl (" + GLContext(GLBackend::EGL, 0).renderer() + "); R = 32]"), std::string::npos)
      << device0.output;
  // --backend auto: at R = 2 (24 pixels) the rule for CPUs takes Embree for the plane's patches; on a GPU, GL.
  const auto autoRun = test::run(run + "2 --backend auto --gl egl");
  ASSERT_EQ(autoRun.exitCode, 0) << autoRun.output;
  const std::string expected = isSoftwareRenderer(renderer) ? "[auto: embree; R = 2]" : "[auto: gl (" + renderer + "); R = 2]";
  EXPECT_NE(autoRun.output.find(expected), std::string::npos) << autoRun.output;
}

TEST(GLDevice, SoftwareRenderersAreRecognised) {
  EXPECT_TRUE(isSoftwareRenderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
  EXPECT_TRUE(isSoftwareRenderer("softpipe"));
  EXPECT_FALSE(isSoftwareRenderer("NVIDIA H100 80GB HBM3/PCIe/SSE2"));
  EXPECT_FALSE(isSoftwareRenderer("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.54)"));
}

TEST(TableCompare, FindsAChangedFactorAndNothingElse) {
  const SceneDesc scene = loadScene(kPlane);
  PreprocessOptions o = defaultOptions(scene);
  o.settings.backend = "embree", o.settings.resolution = 32;
  const FirstShotTable ref = preprocessScene(scene, o);
  ASSERT_GT(ref.nonZeros(), 10u);
  const TableDifference same = compareTables(ref, ref);
  EXPECT_TRUE(same.sameSamples && same.sameMesh);
  EXPECT_EQ(same.differingFactors, 0u);
  EXPECT_EQ(same.weightedL1, 0.0);
  EXPECT_EQ(same.maxSampleFlux, 0.0);
  FirstShotTable changed = ref;
  const size_t k = ref.nonZeros() / 2;
  changed.factor[k] *= 1.5f;
  const TableDifference d = compareTables(ref, changed);
  EXPECT_EQ(d.differingFactors, 1u);
  EXPECT_NEAR(d.maxFactor, 0.5, 1e-6);
  double mass = 0, patchArea = 0;  // the expected weighted L1: A_j · 0.5 r_k / Σ A r
  for (uint32_t j = 0; j < ref.mesh.size(); ++j)
    for (uint64_t q = ref.rowStart[j]; q < ref.rowStart[j + 1]; ++q) {
      mass += ref.mesh.patches[j].area * ref.factor[q];
      if (q == k) patchArea = ref.mesh.patches[j].area;
    }
  EXPECT_NEAR(d.weightedL1, patchArea * 0.5 * ref.factor[k] / mass, 1e-6 * d.weightedL1);
  EXPECT_NEAR(d.totalFlux, d.weightedL1, 1e-6 * d.weightedL1);  // one point light: one sample holds all the flux
  EXPECT_GT(d.maxSampleFlux, 0.0);
}

}  // namespace
}  // namespace firstshot
