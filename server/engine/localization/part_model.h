#pragma once
// A part as the localizer matches it: its surface samples at the voxel and at the point-pair step,
// a kd-tree over them in the part's frame, and its point-pair table.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "localization/oriented_points.h"
#include "localization/ppf_voting.h"
#include "registration/target_index.h"
#include "spatial/kd_tree.h"
#include "vscan/common/mesh.h"
#include "vscan/common/status.h"

namespace vscan::localization {

struct PartModelSettings {
  double voxel_size = 0;  // 0: DefaultVoxel
  size_t samples = 20000;
  double ppf_step_voxels = 2.5;
  double angle_step_rad = 0.2094;
  unsigned scene_reference_stride = 5;
};

struct PartModel {
  // About what the model holds in memory (its pair table, mostly).
  size_t MemoryBytes() const;

  OrientedPoints model;       // thinned to the voxel
  OrientedPoints ppf_points;  // thinned to the PPF step
  std::vector<Eigen::Vector3f> ppf_rims;  // RimDirections of ppf_points
  double voxel = 0, ppf_step = 0;
  Eigen::AlignedBox3f bounds;  // part frame
  double extent = 0;           // the bounding box's diagonal
  std::unique_ptr<spatial::KdTree> model_tree;  // over model.points, part frame
  std::unique_ptr<registration::TargetIndex> icp_target;  // model, for ICP onto it
  std::unique_ptr<PpfModel> ppf;
};

// The part's bounding-box diagonal / 50, or its middle extent / 10 when that is smaller (a long
// thin part is not reduced to a line).
double DefaultVoxel(const TriangleMesh& part);

// Rims (boundary_points.h) are looked for within this many PPF steps, in the part and the scan alike.
inline constexpr double kRimRadiusInPpfSteps = 2;

// InvalidArgument naming field for a part without area; ResourceExhausted naming
// "options.voxel_size" when a voxel the caller chose leaves too many points for the pair table.
StatusOr<PartModel> BuildPartModel(const TriangleMesh& part, const std::string& field, const PartModelSettings& settings);

}  // namespace vscan::localization
