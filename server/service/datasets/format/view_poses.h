#pragma once
// Where each view of a scene looks from (DatasetViews): a direction within the plan's cone about
// the bin's up axis and a distance within its range, both drawn from the view's seed, looking at
// the centre of the bin's floor.

#include <cstdint>

#include "service/datasets/format/dataset_plan.h"
#include "vscan/common/pose.h"

namespace vscan::service::dataset {

// The seed a view's pose is drawn from, from the scene's own seed and the view index.
uint64_t ViewPoseSeed(uint64_t scene_seed, uint32_t view);

// bin_from_camera (camera axes x right, y down, z forward; the bin's floor centre at its origin,
// z up). A view straight down (cone 0) is exactly x along the bin's x, y along its -y.
Pose3 SampleViewPose(const DatasetPlan& plan, uint64_t view_seed);

}  // namespace vscan::service::dataset
