#include "raster/scene_geometry.h"

#include <cmath>
#include <limits>
#include <string>

namespace vscan::raster {
namespace {

std::string Field(size_t i) { return "instances[" + std::to_string(i) + "]"; }

Status CheckInstance(const raycast::SceneInstance& instance, size_t i) {
  if (instance.mesh == nullptr) return InvalidArgument(Field(i) + ".mesh: missing");
  if (!std::isfinite(instance.scale) || instance.scale <= 0) {
    return InvalidArgument(Field(i) + ".scale: must be finite and positive");
  }
  if (!instance.world_from_object.matrix().allFinite()) {
    return InvalidArgument(Field(i) + ".world_from_object: NaN or infinite value");
  }
  const TriangleMesh& mesh = *instance.mesh;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (uint32_t index : mesh.triangles[t]) {
      if (index >= mesh.vertices.size()) {
        return InvalidArgument(Field(i) + ".mesh.triangles[" + std::to_string(t) + "]: vertex index " +
                               std::to_string(index) + " out of range (" + std::to_string(mesh.vertices.size()) +
                               " vertices)");
      }
    }
  }
  return Status::Ok();
}

// World-frame vertices of one instance, in double precision.
StatusOr<std::vector<Eigen::Vector3d>> WorldVertices(const raycast::SceneInstance& instance, size_t i) {
  std::vector<Eigen::Vector3d> world;
  world.reserve(instance.mesh->vertices.size());
  for (const Eigen::Vector3f& v : instance.mesh->vertices) {
    const Eigen::Vector3d w = instance.world_from_object * (instance.scale * v.cast<double>());
    if (!w.cast<float>().allFinite()) {
      return InvalidArgument(Field(i) + ".mesh.vertices[" + std::to_string(world.size()) +
                             "]: not finite in the world frame");
    }
    world.push_back(w);
  }
  return world;
}

}  // namespace

StatusOr<SceneGeometry> BuildSceneGeometry(std::span<const raycast::SceneInstance> instances) {
  uint64_t vertex_count = 0, face_count = 0;
  for (size_t i = 0; i < instances.size(); ++i) {
    RETURN_IF_ERROR(CheckInstance(instances[i], i));
    if (instances[i].mesh->empty()) continue;
    vertex_count += instances[i].mesh->vertices.size();
    face_count += instances[i].mesh->triangles.size();
  }
  if (vertex_count > std::numeric_limits<uint32_t>::max() || 3 * face_count > std::numeric_limits<uint32_t>::max()) {
    return ResourceExhausted("instances: more than 2^32 vertices or indices in one scene");
  }

  std::vector<std::vector<Eigen::Vector3d>> world(instances.size());
  auto faces = std::make_shared<SceneFaces>();
  for (size_t i = 0; i < instances.size(); ++i) {
    if (instances[i].mesh->empty()) continue;
    ASSIGN_OR_RETURN(world[i], WorldVertices(instances[i], i));
    for (const Eigen::Vector3d& w : world[i]) faces->world_box.extend(w);
  }
  if (!faces->world_box.isEmpty()) faces->centre = faces->world_box.center();

  SceneGeometry geometry;
  geometry.vertices.reserve(vertex_count);
  geometry.triangles.reserve(face_count);
  faces->normals.reserve(face_count);
  faces->instance_ids.reserve(face_count);
  for (size_t i = 0; i < instances.size(); ++i) {
    if (instances[i].mesh->empty()) continue;
    const auto base = static_cast<uint32_t>(geometry.vertices.size());
    for (const Eigen::Vector3d& w : world[i]) geometry.vertices.push_back((w - faces->centre).cast<float>());
    for (const auto& t : instances[i].mesh->triangles) {
      geometry.triangles.push_back({base + t[0], base + t[1], base + t[2]});
      const Eigen::Vector3d& a = world[i][t[0]];
      const Eigen::Vector3d n = (world[i][t[1]] - a).cross(world[i][t[2]] - a);
      const double length = n.norm();
      faces->normals.push_back(length > 0 ? Eigen::Vector3f((n / length).cast<float>()) : Eigen::Vector3f::Zero());
      faces->instance_ids.push_back(instances[i].instance_id);
    }
  }
  geometry.faces = std::move(faces);
  return geometry;
}

}  // namespace vscan::raster
