#pragma once
// A scene's mounted robots as geometry: their link meshes, parsed like mesh uploads (robot
// bundles are user data), and the mounts of a scene.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_registry/link_geometry.h"
#include "robot_registry/robot_registry.h"
#include "scenes/scene_registry.h"

namespace vscan::service {

// STL, OBJ and PLY files through the registry's import path; other formats (e.g. COLLADA) are
// refused, so the link falls back to its other geometry.
robot_registry::LinkMeshImporter LinkMeshImporter(scenes::SceneRegistry& registry);

// Every mount of the scene, in mount id order.
StatusOr<std::vector<store::MountRecord>> SceneMounts(robot_registry::RobotRegistry& robots,
                                                       const std::string& scene_id);

// The joint positions of a mount nobody commands: zero, clamped into the limits.
Eigen::VectorXd HomePositions(const robot::KinematicChain& chain);

}  // namespace vscan::service
