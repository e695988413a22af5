#pragma once
// scene_pickable.json (docs/DATASETS.md, "Picks"): one entry per part in scene_gt.json's order,
// whether the plan's robot can pick it and with which grasp.

#include <string>

#include "service/datasets/format/dataset_frame.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// frame.picks must hold a record for every object of the frame (INTERNAL otherwise). The tool pose
// is BOP-style: R row-major, t in millimetres, world frame (scene_camera.json's cam_R_w2c world).
StatusOr<std::string> ScenePickableJson(const DatasetFrame& frame);

}  // namespace vscan::service::dataset
