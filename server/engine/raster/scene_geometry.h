#pragma once
// A scene's instances flattened into one world-frame triangle list, ready to upload, with the
// per-face data that decoding needs.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "raycast/raycast_scene.h"
#include "vscan/common/status.h"

namespace vscan::raster {

// Indexed by the face index the shaders write; shared with the threads that decode frames.
struct SceneFaces {
  std::vector<Eigen::Vector3f> normals;  // world frame, unit; zero for a degenerate face
  std::vector<uint32_t> instance_ids;
  Eigen::AlignedBox3d world_box;         // empty for a scene without triangles
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the origin of the uploaded coordinates

  size_t size() const { return normals.size(); }
};

struct SceneGeometry {
  // Relative to faces->centre, so that single precision keeps its resolution far from the origin.
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;  // into vertices
  std::shared_ptr<SceneFaces> faces;
};

// world_point = world_from_object * (scale * mesh_point), as RaycastScene places instances.
// Checks the instances and names the first bad field.
StatusOr<SceneGeometry> BuildSceneGeometry(std::span<const raycast::SceneInstance> instances);

}  // namespace vscan::raster
