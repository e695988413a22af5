#include "paging.h"
#include "unary_call.h"

namespace vscan::client {

using SceneStub = v1::SceneService::Stub;

StatusOr<v1::Scene> Client::CreateScene(const std::string& name) {
  v1::CreateSceneRequest request;
  request.set_name(name);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *scenes_, &SceneStub::CreateScene, request));
  return std::move(*response.mutable_scene());
}

StatusOr<v1::Scene> Client::GetScene(const std::string& scene_id) {
  v1::GetSceneRequest request;
  request.set_scene_id(scene_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *scenes_, &SceneStub::GetScene, request));
  return std::move(*response.mutable_scene());
}

StatusOr<std::vector<v1::Scene>> Client::ListScenes() {
  return CollectPages<v1::Scene>(
      [this](const std::string& token) {
        v1::ListScenesRequest request;
        request.set_page_token(token);
        return UnaryCall(*this, *scenes_, &SceneStub::ListScenes, request);
      },
      [](const v1::ListScenesResponse& page) -> const auto& { return page.scenes(); });
}

Status Client::DeleteScene(const std::string& scene_id) {
  v1::DeleteSceneRequest request;
  request.set_scene_id(scene_id);
  return UnaryCall(*this, *scenes_, &SceneStub::DeleteScene, request).status();
}

StatusOr<v1::AddObjectResponse> Client::AddObject(const std::string& scene_id, const std::string& mesh_id,
                                                  const ObjectPlacement& placement) {
  v1::AddObjectRequest request;
  request.set_scene_id(scene_id);
  request.set_mesh_id(mesh_id);
  if (placement.pose.kind_case() != v1::Pose::KIND_NOT_SET) *request.mutable_pose() = placement.pose;
  request.set_scale(placement.scale);
  request.set_label(placement.label);
  request.set_on_table(placement.on_table);
  if (placement.material) *request.mutable_material() = *placement.material;
  return UnaryCall(*this, *scenes_, &SceneStub::AddObject, request);
}

StatusOr<v1::MoveObjectResponse> Client::MoveObject(const std::string& scene_id, const std::string& object_id,
                                                    const std::optional<v1::Pose>& pose, double scale) {
  v1::MoveObjectRequest request;
  request.set_scene_id(scene_id);
  request.set_object_id(object_id);
  request.set_scale(scale);
  if (pose) {
    *request.mutable_pose() = *pose;
  } else {
    // The request carries a full pose, so re-send the current one.
    ASSIGN_OR_RETURN(const v1::Scene scene, GetScene(scene_id));
    const v1::SceneObject* found = nullptr;
    for (const auto& object : scene.objects())
      if (object.object_id() == object_id) found = &object;
    if (!found) return NotFound("object_id: no object '" + object_id + "' in scene '" + scene_id + "'");
    *request.mutable_pose() = found->pose();
  }
  return UnaryCall(*this, *scenes_, &SceneStub::MoveObject, request);
}

StatusOr<v1::SetObjectMaterialResponse> Client::SetObjectMaterial(const std::string& scene_id,
                                                                  const std::string& object_id,
                                                                  const std::optional<v1::Material>& material) {
  v1::SetObjectMaterialRequest request;
  request.set_scene_id(scene_id);
  request.set_object_id(object_id);
  if (material) *request.mutable_material() = *material;
  return UnaryCall(*this, *scenes_, &SceneStub::SetObjectMaterial, request);
}

StatusOr<std::vector<v1::MaterialPreset>> Client::ListMaterialPresets() {
  ASSIGN_OR_RETURN(auto response,
                   UnaryCall(*this, *scenes_, &SceneStub::ListMaterialPresets, v1::ListMaterialPresetsRequest{}));
  return std::vector<v1::MaterialPreset>(response.presets().begin(), response.presets().end());
}

StatusOr<uint64_t> Client::RemoveObject(const std::string& scene_id, const std::string& object_id) {
  v1::RemoveObjectRequest request;
  request.set_scene_id(scene_id);
  request.set_object_id(object_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *scenes_, &SceneStub::RemoveObject, request));
  return response.revision();
}

StatusOr<v1::SetRotaryTableResponse> Client::SetRotaryTable(const std::string& scene_id,
                                                            const v1::RotaryTable& table) {
  v1::SetRotaryTableRequest request;
  request.set_scene_id(scene_id);
  *request.mutable_table() = table;
  return UnaryCall(*this, *scenes_, &SceneStub::SetRotaryTable, request);
}

}  // namespace vscan::client
