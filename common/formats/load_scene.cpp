// A scene file of any format → SceneDesc, by its extension.
#include "common/formats/load_scene.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/formats/assets/mesh_import.h"
#include "common/formats/json/scene_json.h"
#include "common/formats/mitsuba/scene_mitsuba.h"
#include "common/util/error.h"

namespace firstshot {

SceneDesc loadScene(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (!std::filesystem::exists(path)) throw InputError(path, "", "no such file");
  SceneDesc scene;
  if (ext == ".json") {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot open file");
    std::stringstream ss;
    ss << in.rdbuf();
    scene = parseSceneJson(ss.str(), path);
  } else if (ext == ".obj" || ext == ".gltf" || ext == ".glb" || ext == ".ply") {
    scene = importAssetScene(path);
  } else if (ext == ".xml") {
    scene = loadSceneMitsuba(path);
  } else {
    throw InputError(path, "", "unknown scene file type \"" + ext + "\" (expected .json, .xml, .obj, .gltf, .glb or .ply)");
  }
  validateScene(scene);
  return scene;
}

}  // namespace firstshot
