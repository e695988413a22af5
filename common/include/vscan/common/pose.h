#pragma once
// Rigid transforms. Names follow T_target_source: world_from_sensor maps sensor points to world.

#include <string_view>

#include <Eigen/Geometry>

#include "vscan/common/status.h"

namespace vscan {

using Pose3 = Eigen::Isometry3d;

// Checks that m is finite, rigid (orthonormal rotation, det +1, last row 0 0 0 1).
StatusOr<Pose3> PoseFromMatrix(const Eigen::Matrix4d& m, std::string_view field);

// Translation and quaternion (w, x, y, z); the quaternion must be finite and near unit length.
StatusOr<Pose3> PoseFromQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q,
                                   std::string_view field);

// world_from_sensor of a camera at eye looking at target: z forward, x right, y down.
StatusOr<Pose3> PoseFromLookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                               const Eigen::Vector3d& up, std::string_view field);

// Rotation by angle_rad about the line through centre along axis (axis need not be unit).
Pose3 RotationAboutLine(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double angle_rad);

bool AllFinite(const Eigen::Vector3d& v);

}  // namespace vscan
