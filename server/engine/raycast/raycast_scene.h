#pragma once
// An Embree scene built from mesh instances. Embree stays private: only the raycast queries reach
// it, through EmbreeOf (embree_scene.h).

#include <cstdint>
#include <memory>
#include <span>

#include "sensor/material.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::raycast {

// One mesh placed in the world: world_point = world_from_object * (scale * mesh_point).
struct SceneInstance {
  std::shared_ptr<const TriangleMesh> mesh;
  Pose3 world_from_object = Pose3::Identity();
  double scale = 1.0;
  uint32_t instance_id = 0;
  // What its surface is made of (scenes/object_material.h resolves it); scans do not read it yet.
  sensor::Material material = sensor::DefaultMaterial();
};

class RaycastScene {
 public:
  // Builds and commits the acceleration structure; an empty list gives a scene that hits nothing.
  static StatusOr<std::shared_ptr<const RaycastScene>> Build(std::span<const SceneInstance> instances);
  ~RaycastScene();
  RaycastScene(const RaycastScene&) = delete;
  RaycastScene& operator=(const RaycastScene&) = delete;

  uint64_t triangle_count() const;
  // Instance id of Embree geometry geom_id (0 when out of range).
  uint32_t InstanceOfGeometry(uint32_t geom_id) const;

 private:
  // Embree's scene and geometry (embree_scene.h); only the raycast queries reach it, via EmbreeOf.
  struct Impl;
  friend const Impl& EmbreeOf(const RaycastScene& scene);
  explicit RaycastScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace vscan::raycast
