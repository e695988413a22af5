#pragma once
// Physical bounds on geometric inputs, checked where a value enters (docs/API.md, "Bounds").
// They keep every derived quantity far inside float range, so that no ray vscan builds is one that
// Embree or OpenGL rejects.

#include <string>
#include <string_view>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan {

// Any position, translation, eye, target, mount base, tool offset or URDF origin: metres from the
// origin of its frame, per coordinate.
inline constexpr double kMaxCoordinateM = 1e4;
// A mesh vertex or a placed object's vertex in the world, per coordinate, in metres.
inline constexpr double kMaxMeshCoordinateM = 1e4;
// Pinhole focal lengths, in pixels.
inline constexpr double kMinFocalPx = 1e-2;
inline constexpr double kMaxFocalPx = 1e8;
// Tangent of the widest pixel ray off the optical axis (89.94 degrees): a field of view below 180.
inline constexpr double kMaxRayTangent = 1e3;
// Depth range of a sensor, in metres.
inline constexpr double kMinNearM = 1e-6;
inline constexpr double kMaxFarM = 1e5;

// INVALID_ARGUMENT naming field unless every coordinate of p is finite and within kMaxCoordinateM.
Status CheckPosition(const Eigen::Vector3d& p, std::string_view field);

}  // namespace vscan
