#pragma once
// The ground truth of a finished dataset as its BOP files hold it (docs/DATASETS.md): the scene
// count, each part type's model (models_info.json, models/obj_<obj_id>.ply) and each image's true
// poses and visible fractions (scene_gt.json, scene_gt_info.json). Lengths in millimetres, as in
// the files. A file that is missing or does not hold what the layout says is DATA_LOSS naming it.

#include <cstdint>
#include <filesystem>
#include <map>
#include <vector>

#include <Eigen/Core>

#include "localization/part_symmetries.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::service {

struct DatasetModel {
  uint32_t obj_id = 0;
  double diameter_mm = 0;
  localization::PartSymmetries symmetries;  // millimetres
};

struct TrueObject {
  uint32_t obj_id = 0;
  Pose3 camera_from_model = Pose3::Identity();  // millimetres
  double visib_fract = 0;
};

// im_id to the image's ground-truth objects in the file's order.
using SceneTruth = std::map<uint32_t, std::vector<TrueObject>>;

// dataset.json's scene_count; FAILED_PRECONDITION when scenes.json (written by the merge, the last
// step) is absent: the dataset is not finished.
StatusOr<uint64_t> ReadDatasetSceneCount(const std::filesystem::path& root);
StatusOr<std::map<uint32_t, DatasetModel>> ReadDatasetModels(const std::filesystem::path& root);
StatusOr<std::vector<Eigen::Vector3f>> ReadModelVertices(const std::filesystem::path& root, uint32_t obj_id);
StatusOr<SceneTruth> ReadSceneTruth(const std::filesystem::path& root, uint64_t scene_id);

}  // namespace vscan::service
