#pragma once
// What the web view's API sends: scenes as JSON, meshes in a compact binary layout.

#include <cstdint>
#include <string>
#include <vector>

#include "sensor/material.h"
#include "store/catalogue.h"
#include "store/robot_catalogue.h"
#include "vscan/common/mesh.h"

namespace vscan::web {

// An object as the page draws it: its record, its world pose and the material in effect (the
// object's, else its mesh's, else the default) with its preset's name (empty for explicit values).
struct PlacedObject {
  store::ObjectRecord object;
  Eigen::Matrix4d world_from_object = Eigen::Matrix4d::Identity();
  std::string material_preset;
  sensor::Material material;
};

// {"scenes":[{"scene_id","name","revision","object_count"}]}
std::string ScenesJson(const std::vector<store::SceneRecord>& scenes);
// {"scene_id","name","revision","objects":[{"object_id","label","mesh_id","instance_id","scale",
//   "world_from_object": 4 rows of 4,"material": {"preset","albedo","metallic","roughness",
//   "specular_reflectance"}}]}
//   "table": {"enabled","angle_deg","centre","axis"}, "mounts": [{"mount_id","robot_id"}]
std::string SceneJson(const store::SceneRecord& scene, const std::vector<PlacedObject>& objects,
                      const std::vector<store::MountRecord>& mounts);

// A mounted robot in a pose: its mount, joint positions and where its sensor (the tool) stands.
struct MountPose {
  store::MountRecord mount;
  Eigen::VectorXd joints;
  Eigen::Matrix4d world_from_sensor = Eigen::Matrix4d::Identity();
};
// One link shape placed in the world; its mesh is served by index.
struct MountShape {
  std::string link;
  const TriangleMesh* mesh = nullptr;
  Eigen::Matrix4d world_from_shape = Eigen::Matrix4d::Identity();
};
// {"mount_id","robot_id","scene_id","joints":[...],"world_from_base","world_from_sensor",
//  "shapes":[{"link","triangles","world_from_shape"}]} (matrices as 4 rows of 4)
std::string MountJson(const MountPose& pose, const std::vector<MountShape>& shapes);

// Little-endian: "VSMH", uint32 version (1), uint32 vertex count, uint32 triangle count, then
// float32 x y z per vertex (metres, the mesh's own frame), then uint32 a b c per triangle.
inline constexpr char kMeshMagic[4] = {'V', 'S', 'M', 'H'};
inline constexpr uint32_t kMeshLayoutVersion = 1;
std::string MeshBinary(const TriangleMesh& mesh);

}  // namespace vscan::web
