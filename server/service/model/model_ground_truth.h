#pragma once
// The true surface a model job is judged against: the scene's objects on its table (all its objects
// when none stands on the table), placed with the table at 0 degrees and merged into one mesh in the
// model frame.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "service/model/model_crop.h"
#include "scenes/scene_registry.h"
#include "store/catalogue.h"
#include "vscan/common/mesh.h"

namespace vscan::service {

struct ModelGroundTruth {
  TriangleMesh mesh;  // model frame
  std::vector<std::string> object_ids;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // of the bounding box
  double diagonal = 0;                               // of the bounding box, metres
};

StatusOr<ModelGroundTruth> LoadGroundTruth(scenes::SceneRegistry& registry, const store::SceneRecord& scene);

// The default crop about the truth: about the table's axis, or the vertical through the truth's
// centre when the scene has no table.
ModelCrop DefaultCrop(const ModelGroundTruth& truth, const store::SceneRecord& scene);

}  // namespace vscan::service
