#pragma once
// A deterministic stand-in for a scanned bin: a square floor and two boxes seen from above, cast
// analytically per pixel. The seed moves and turns the boxes, the bin index spreads them apart, the
// sensor index picks the resolution. The taller box may cover part of the other.

#include <vector>

#include "service/datasets/format/dataset_frame.h"
#include "service/datasets/format/dataset_plan.h"
#include "service/datasets/format/dataset_run.h"

namespace vscan::test {

inline constexpr uint32_t kFloorInstance = 1;
inline constexpr double kCameraHeightM = 0.8;
inline constexpr double kFloorHalfSideM = 0.3;

struct SyntheticBox {
  uint32_t obj_id = 0;
  uint32_t instance_id = 0;
  Eigen::Vector3d half_extent_m;
  Pose3 world_from_object;  // centre of the box
};

// Two bins, three seeds, two sensors: twelve scenes of one view each, from kCameraHeightM.
service::dataset::DatasetPlan SyntheticPlan();
// The same scenes with three views each, sampled within 35 degrees of straight down, 0.7-0.9 m away.
service::dataset::DatasetPlan SyntheticMultiViewPlan();
std::vector<SyntheticBox> SyntheticBoxes(const service::dataset::SceneKey& key);
service::dataset::CameraIntrinsics SyntheticCamera(size_t sensor_index);
// Looks straight down from kCameraHeightM above the floor's centre.
Pose3 SyntheticWorldFromCamera();
// The view's pose is the plan's (SampleViewPose): view 0 of SyntheticPlan is SyntheticWorldFromCamera.
service::dataset::DatasetFrame SyntheticFrame(const service::dataset::DatasetPlan& plan,
                                              const service::dataset::SceneKey& key, uint32_t view = 0);
service::dataset::DatasetFrame SyntheticFrame(const service::dataset::SceneKey& key);
// SyntheticFrame of the plan as a FrameSource; the plan must outlive it.
service::dataset::FrameSource SyntheticSource(const service::dataset::DatasetPlan& plan);
// Seed 12's far-pair asks for one part more than its two boxes: a bin that was full.
bool SyntheticUnderfilled(const service::dataset::SceneKey& key);
// The two box types as part models: obj 1 with its two-fold turn about z, obj 2 with its four-fold.
std::vector<service::dataset::PartModel> SyntheticParts();

}  // namespace vscan::test
