// Grouped factors in the .fsd file (common/table/firstshot_groups.h): the table read back is the
// preprocessor's bit for bit, the file shrinks by about the light's vertex count where the light
// is fully visible, and a compact table renders the same image as the table it was written from.
#include <gtest/gtest.h>

#include <bit>
#include <filesystem>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "common/table/firstshot_groups.h"
#include "preprocess/preprocessor.h"
#include "render/scene/render_scene.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// The Cornell box (one area light, fully visible to most patches) at 32 × 32 pixels, its table at R = 64.
SceneDesc cornell(bool glossy) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 32;
  if (glossy)
    for (MaterialDesc& m : desc.materials)
      if (m.name == "white") m.type = MaterialType::Glossy, m.albedo *= 0.6f, m.specular = Color(0.3f), m.exponent = 30;
  return desc;
}

FirstShotTable preprocess(const SceneDesc& desc) {
  PreprocessOptions o = defaultOptions(desc);
  o.settings.resolution = 64;
  o.settings.patchSize = o.settings.minPatchSize = 0.025;  // uniform 0.025 m: grouping is about one mesh's factors
  o.threads = 2;
  o.quiet = true;
  return preprocessScene(desc, o);
}

/// Bitwise equality of float arrays (== would equate 0 and −0).
bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k)
    if (std::bit_cast<uint32_t>(a[k]) != std::bit_cast<uint32_t>(b[k])) return false;
  return true;
}

}  // namespace

TEST(FsdGroups, ReadBackIsBitIdenticalToThePreprocessorsTable) {
  const SceneDesc desc = cornell(false);
  const FirstShotTable t = preprocess(desc);
  const GroupedFactors g = groupFactors(t);
  ASSERT_GT(g.groupLight.size(), 0u) << "no groups: nothing tested";
  const std::string path = test::tempDir() + "/cornell.fsd";
  writeFirstShot(path, t);
  const FirstShotTable r = readFirstShot(path, hashScene(desc));
  EXPECT_EQ(r.rowStart, t.rowStart);
  EXPECT_EQ(r.sampleIndex, t.sampleIndex);
  EXPECT_TRUE(sameBits(r.factor, t.factor));
  EXPECT_EQ(r.areaEyeOffset, t.areaEyeOffset);
  // The visible fractions handed to the renderer are those it would recover itself.
  ASSERT_EQ(r.visible.size(), r.factor.size());
  std::vector<float> own(t.factor.size());
  for (uint32_t j = 0; j < t.mesh.size(); ++j)
    for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k)
      own[k] = recoveredVisible(t.factor[k], t.samples[t.sampleIndex[k]], t.areaEyeOffset, t.mesh.patches[j]);
  EXPECT_TRUE(sameBits(r.visible, own));
}

// Most patches see the whole light: one group replaces the light's ~100 factors there.
TEST(FsdGroups, FullyVisibleLightShrinksTheFile) {
  const SceneDesc desc = cornell(false);
  const FirstShotTable t = preprocess(desc);
  const GroupedFactors g = groupFactors(t);
  const size_t entries = g.singleSample.size() + g.groupLight.size();
  EXPECT_LT(entries * 4, t.nonZeros()) << g.singleSample.size() << " singles, " << g.groupLight.size() << " groups";
  // Each grouped factor is a factor of the table, each single one too, and no factor is lost.
  size_t grouped = 0;
  for (uint32_t j = 0; j < t.mesh.size(); ++j) grouped += g.rowCount[j] - g.singleCount[j];
  EXPECT_EQ(grouped + g.singleSample.size(), t.nonZeros());
  // On disk: the patches, the samples and 8 bytes per entry (plus 12 per patch for the counts).
  const std::string path = test::tempDir() + "/cornell.fsd";
  writeFirstShot(path, t);
  const uint64_t size = std::filesystem::file_size(path);
  const uint64_t fixed = 1024 + 92 * uint64_t(t.mesh.size()) + 48 * t.samples.size() + 12 * uint64_t(t.mesh.size());
  EXPECT_LE(size, fixed + 8 * entries);
  EXPECT_LT(size, fixed + 8 * t.nonZeros() / 4);  // against 8 bytes per factor in version 2
}

// Compact vs full table: the same factors and visible fractions, so the same image, diffuse or glossy.
TEST(FsdGroups, CompactTableRendersTheSameImage) {
  for (bool glossy : {false, true}) {
    const SceneDesc desc = cornell(glossy);
    FirstShotTable t = preprocess(desc);
    const std::string path = test::tempDir() + "/table.fsd";
    writeFirstShot(path, t);
    const RenderScene full(desc, std::move(t)), compact(desc, readFirstShot(path, hashScene(desc)));
    IntegratorOptions io;
    io.primary = PrimaryMode::Patch;
    const auto a = test::renderPath(full, io, 4, 7, 1), b = test::renderPath(compact, io, 4, 7, 1);
    size_t differ = 0;
    for (int y = 0; y < a.film.height(); ++y)
      for (int x = 0; x < a.film.width(); ++x) differ += a.film.mean(x, y) != b.film.mean(x, y);
    EXPECT_EQ(differ, 0u) << (glossy ? "glossy" : "diffuse");
  }
}
