// KHR_materials_transmission (and _volume) as glass (common/formats/assets/gltf_materials.h): a thin-walled transmitting
// material is a thin glass pane whose transmittance is base colour × transmission × a lossless pane's; with a volume
// it is a solid dielectric; a metal ignores transmission; a rough one is rough glass, with nothing on stderr;
// and the extension is not reported as unsupported.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/formats/assets/mesh_import.h"
#include "common/materials/thin_glass.h"
#include "common/scene/scene_desc.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

/// Writes a one-triangle glTF (positions in a data URI) whose material is @p material (JSON); @return its path.
std::string writeTriangle(const std::string& material, const std::string& extensionsUsed) {
  // Three vec3 floats: (0,0,0), (1,0,0), (0,1,0), base64 of their 36 little-endian bytes.
  const std::string positions = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
  const std::string path = test::tempDir() + "/tri.gltf";
  test::writeText(path, R"({"asset": {"version": "2.0"}, "extensionsUsed": [)" + extensionsUsed + R"(],
    "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
    "materials": [)" + material + R"(],
    "buffers": [{"uri": "data:application/octet-stream;base64,)" + positions + R"(", "byteLength": 36}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]})");
  return path;
}

MaterialDesc triangleMaterial(const std::string& material, const std::string& used = R"("KHR_materials_transmission")") {
  const SceneDesc s = importAssetScene(writeTriangle(material, used));
  EXPECT_EQ(s.shapes.size(), 1u);
  return s.materials.at(s.shapes.at(0).material);
}

TEST(GltfTransmission, ThinWalledIsAThinGlassPane) {
  testing::internal::CaptureStderr();
  const MaterialDesc m = triangleMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1],
      "metallicFactor": 0, "roughnessFactor": 0},
      "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.8}}})");
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(m.type, MaterialType::ThinGlass);
  EXPECT_EQ(m.glassRoughness, 0.0f);  // smooth: the delta pane
  EXPECT_FLOAT_EQ(m.ior, 1.5f);
  const float most = ThinGlassBSDF::maxTransmittance(1.5f);  // 0.923
  EXPECT_NEAR(m.transmittance.x, 0.8f * most, 1e-6);
  EXPECT_NEAR(m.transmittance.y, 0.4f * most, 1e-6);
  EXPECT_NEAR(m.transmittance.z, 0.2f * most, 1e-6);
  EXPECT_EQ(err.find("not supported"), std::string::npos) << err;  // read, not ignored
  EXPECT_EQ(err.find("rough"), std::string::npos) << err;          // smooth: nothing to say
}

TEST(GltfTransmission, VolumeIsASolidDielectric) {
  const MaterialDesc m = triangleMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 1, 0.9, 1],
      "metallicFactor": 0, "roughnessFactor": 0},
      "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                     "KHR_materials_volume": {"thicknessFactor": 0.02},
                     "KHR_materials_ior": {"ior": 1.33}}})",
                                          R"("KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior")");
  EXPECT_EQ(m.type, MaterialType::Dielectric);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_NEAR(m.transmittance.x, 0.9f, 1e-6);
  EXPECT_NEAR(m.transmittance.y, 1.0f, 1e-6);
}

TEST(GltfTransmission, MetalIgnoresItAndRoughIsRoughGlass) {
  // The default metallic factor is 1: a metal transmits nothing.
  const MaterialDesc metal = triangleMaterial(R"({"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}})");
  EXPECT_EQ(metal.type, MaterialType::Pbr);
  testing::internal::CaptureStderr();
  const MaterialDesc frosted = triangleMaterial(R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.4},
      "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}})");
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(frosted.type, MaterialType::ThinGlass);
  EXPECT_FLOAT_EQ(frosted.glassRoughness, 0.4f);
  EXPECT_EQ(err.find("rough"), std::string::npos) << err;  // rendered rough: nothing to say
}

}  // namespace
}  // namespace firstshot
