#include "service/model/model_ground_truth.h"

#include <algorithm>

#include "scenes/scene_registry.h"

namespace vscan::service {

StatusOr<ModelGroundTruth> LoadGroundTruth(scenes::SceneRegistry& registry, const store::SceneRecord& scene) {
  const bool any_on_table = scene.table.enabled && std::any_of(scene.objects.begin(), scene.objects.end(),
                                                               [](const store::ObjectRecord& o) { return o.on_table; });
  ModelGroundTruth truth;
  for (const store::ObjectRecord& object : scene.objects) {
    if (any_on_table && !object.on_table) continue;
    ASSIGN_OR_RETURN(const auto mesh, registry.LoadMesh(object.mesh_id));
    const Pose3 model_from_object = scenes::SceneRegistry::WorldFromObject(scene, object, 0.0);
    const auto first = static_cast<uint32_t>(truth.mesh.vertices.size());
    for (const Eigen::Vector3f& v : mesh->vertices) {
      truth.mesh.vertices.push_back((model_from_object * (object.scale * v.cast<double>())).cast<float>());
    }
    for (const auto& t : mesh->triangles) truth.mesh.triangles.push_back({first + t[0], first + t[1], first + t[2]});
    truth.object_ids.push_back(object.object_id);
  }
  if (truth.mesh.empty()) {
    return FailedPrecondition("scene_id", "scene '" + scene.scene_id + "' holds no objects to evaluate against");
  }
  Eigen::Vector3f min, max;
  truth.mesh.Bounds(min, max);
  truth.centre = ((min + max) / 2).cast<double>();
  truth.diagonal = (max - min).cast<double>().norm();
  return truth;
}

ModelCrop DefaultCrop(const ModelGroundTruth& truth, const store::SceneRecord& scene) {
  if (scene.table.enabled) return CylinderAround(truth.mesh, scene.table.centre, scene.table.axis);
  return CylinderAround(truth.mesh, truth.centre, Eigen::Vector3d::UnitZ());
}

}  // namespace vscan::service
