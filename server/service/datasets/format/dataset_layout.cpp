#include "service/datasets/format/dataset_layout.h"

#include <cstdio>

namespace vscan::service::dataset {

std::string SixDigits(uint64_t n) {
  char buffer[24];
  std::snprintf(buffer, sizeof(buffer), "%06llu", static_cast<unsigned long long>(n));
  return buffer;
}

std::string CameraFileName(const std::vector<std::string>& sensors, size_t sensor_index) {
  return sensors.size() == 1 ? "camera.json" : "camera_" + sensors[sensor_index] + ".json";
}

std::filesystem::path SceneDir(const std::filesystem::path& root, uint64_t scene_id) {
  return root / kScenesDir / SixDigits(scene_id);
}

std::filesystem::path PartialSceneDir(const std::filesystem::path& root, uint64_t scene_id) {
  return root / kScenesDir / (SixDigits(scene_id) + kPartialSuffix);
}

}  // namespace vscan::service::dataset
