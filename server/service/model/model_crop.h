#pragma once
// The region of the model frame a model job keeps: a box the client gives, or by default a cylinder
// about the table's axis around the ground truth (grown by 2% of its size, starting 1 mm above its
// lowest point, so that the table top and the surface resting on it are cut).

#include <span>
#include <vector>

#include <Eigen/Core>

#include "service/model/model_plan.h"
#include "vscan/common/mesh.h"

namespace vscan::service {

struct ModelCrop {
  enum class Kind { kNone, kBounds, kCylinder };
  Kind kind = Kind::kNone;
  ModelBox box;  // kBounds
  // kCylinder: the axis from base (on the bottom face) along the unit axis, radius and height.
  Eigen::Vector3d base = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double radius = 0;
  double height = 0;

  bool Contains(const Eigen::Vector3f& p) const;
};

inline constexpr double kCropGrowth = 0.02;
inline constexpr double kCropLift = 0.001;

ModelCrop BoxCrop(const ModelBox& box);
// The default crop about truth (model frame): axis through axis_point along axis.
ModelCrop CylinderAround(const TriangleMesh& truth, const Eigen::Vector3d& axis_point, const Eigen::Vector3d& axis);

// The points crop keeps.
std::vector<Eigen::Vector3f> CropPoints(std::span<const Eigen::Vector3f> points, const ModelCrop& crop);

// The part of mesh inside crop: triangles cut exactly at the crop's planes (a box's six faces, a
// cylinder's bottom and top); of a cylinder's side, triangles whose centre lies outside are dropped.
TriangleMesh ClipMesh(const TriangleMesh& mesh, const ModelCrop& crop);

}  // namespace vscan::service
