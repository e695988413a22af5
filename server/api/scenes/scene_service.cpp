#include "api/scenes/scene_service.h"

#include <cmath>

#include "api/scenes/material_convert.h"
#include "api/scenes/scene_convert.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"
#include "sensor/material.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

StatusOr<store::TableRecord> TableFromProto(const v1::RotaryTable& table) {
  store::TableRecord out;
  out.enabled = table.enabled();
  out.centre = FromProto(table.centre());
  out.axis = FromProto(table.axis());
  out.angle_deg = table.angle_deg();
  if (!out.centre.allFinite()) return InvalidArgument("table.centre: NaN or infinite value");
  if (!out.axis.allFinite()) return InvalidArgument("table.axis: NaN or infinite value");
  if (!std::isfinite(out.angle_deg)) return InvalidArgument("table.angle_deg: NaN or infinite value");
  if (out.axis.norm() < 1e-12) out.axis = Eigen::Vector3d::UnitZ();
  out.axis.normalize();
  return out;
}

}  // namespace

grpc::ServerUnaryReactor* SceneService::CreateScene(grpc::CallbackServerContext* ctx,
                                                    const v1::CreateSceneRequest* request,
                                                    v1::CreateSceneResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "CreateScene", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(CheckText(request->name(), "name"));
    ASSIGN_OR_RETURN(auto scene, context_.registry.catalogue().CreateScene(request->name()));
    ToProto(scene, response->mutable_scene());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::GetScene(grpc::CallbackServerContext* ctx, const v1::GetSceneRequest* request,
                                                 v1::GetSceneResponse* response) {
  return RunUnary(ctx, context_.options.token, "GetScene", [&]() -> Status {
    RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    ASSIGN_OR_RETURN(auto scene, context_.registry.catalogue().GetScene(request->scene_id()));
    ToProto(scene, response->mutable_scene());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::ListScenes(grpc::CallbackServerContext* ctx,
                                                   const v1::ListScenesRequest* request,
                                                   v1::ListScenesResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListScenes", [&]() -> Status {
    ASSIGN_OR_RETURN(int limit, PageSize(request->page_size(), context_.options.limits.max_page_size));
    RETURN_IF_ERROR(CheckPageToken(request->page_token(), "scn_"));
    ASSIGN_OR_RETURN(auto scenes, context_.registry.catalogue().ListScenes(request->page_token(), limit + 1));
    const bool more = static_cast<int>(scenes.size()) > limit;
    if (more) scenes.resize(limit);
    for (const auto& scene : scenes) ToProto(scene, response->add_scenes());
    if (more) response->set_next_page_token(scenes.back().scene_id);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::DeleteScene(grpc::CallbackServerContext* ctx,
                                                    const v1::DeleteSceneRequest* request,
                                                    v1::DeleteSceneResponse*) {
  return RunBlockingUnary(ctx, context_.options.token, "DeleteScene", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    return context_.registry.catalogue().DeleteScene(request->scene_id());
  });
}

grpc::ServerUnaryReactor* SceneService::GetMesh(grpc::CallbackServerContext* ctx, const v1::GetMeshRequest* request,
                                                v1::GetMeshResponse* response) {
  return RunUnary(ctx, context_.options.token, "GetMesh", [&]() -> Status {
    RETURN_IF_ERROR(RequireId(request->mesh_id(), "mesh_id"));
    ASSIGN_OR_RETURN(auto mesh, context_.registry.catalogue().GetMesh(request->mesh_id()));
    ToProto(mesh, response->mutable_mesh());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::ListMeshes(grpc::CallbackServerContext* ctx,
                                                   const v1::ListMeshesRequest* request,
                                                   v1::ListMeshesResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListMeshes", [&]() -> Status {
    ASSIGN_OR_RETURN(int limit, PageSize(request->page_size(), context_.options.limits.max_page_size));
    RETURN_IF_ERROR(CheckPageToken(request->page_token(), "msh_"));
    ASSIGN_OR_RETURN(auto meshes, context_.registry.catalogue().ListMeshes(request->page_token(), limit + 1));
    const bool more = static_cast<int>(meshes.size()) > limit;
    if (more) meshes.resize(limit);
    for (const auto& mesh : meshes) ToProto(mesh, response->add_meshes());
    if (more) response->set_next_page_token(meshes.back().mesh_id);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::DeleteMesh(grpc::CallbackServerContext* ctx,
                                                   const v1::DeleteMeshRequest* request, v1::DeleteMeshResponse*) {
  return RunBlockingUnary(ctx, context_.options.token, "DeleteMesh", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->mesh_id(), "mesh_id"));
    return context_.registry.DeleteMesh(request->mesh_id());
  });
}

grpc::ServerUnaryReactor* SceneService::AddObject(grpc::CallbackServerContext* ctx,
                                                  const v1::AddObjectRequest* request,
                                                  v1::AddObjectResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "AddObject", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    RETURN_IF_ERROR(RequireId(request->mesh_id(), "mesh_id"));
    RETURN_IF_ERROR(CheckText(request->label(), "label"));
    store::ObjectRecord object;
    object.scene_id = request->scene_id();
    object.mesh_id = request->mesh_id();
    object.label = request->label();
    object.on_table = request->on_table();
    Pose3 pose = Pose3::Identity();
    if (request->has_pose()) {
      ASSIGN_OR_RETURN(pose, PoseFromProto(request->pose(), "pose"));
    }
    object.pose = pose.matrix();
    ASSIGN_OR_RETURN(object.scale, ScaleOrDefault(request->scale(), "scale"));
    ASSIGN_OR_RETURN(object.material,
                     OptionalMaterialFromProto(request->has_material(), request->material(), "material"));
    ASSIGN_OR_RETURN(auto added, context_.registry.catalogue().AddObject(object));
    ToProto(added.first, response->mutable_object());
    response->set_revision(added.second);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::MoveObject(grpc::CallbackServerContext* ctx,
                                                   const v1::MoveObjectRequest* request,
                                                   v1::MoveObjectResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "MoveObject", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    RETURN_IF_ERROR(RequireId(request->object_id(), "object_id"));
    ASSIGN_OR_RETURN(Pose3 pose, PoseFromProto(request->pose(), "pose"));
    std::optional<double> scale;
    if (request->scale() != 0.0) {
      ASSIGN_OR_RETURN(scale, ScaleOrDefault(request->scale(), "scale"));
    }
    ASSIGN_OR_RETURN(auto moved, context_.registry.catalogue().MoveObject(request->scene_id(), request->object_id(),
                                                                          pose.matrix(), scale));
    ToProto(moved.first, response->mutable_object());
    response->set_revision(moved.second);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::SetObjectMaterial(grpc::CallbackServerContext* ctx,
                                                          const v1::SetObjectMaterialRequest* request,
                                                          v1::SetObjectMaterialResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "SetObjectMaterial", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    RETURN_IF_ERROR(RequireId(request->object_id(), "object_id"));
    ASSIGN_OR_RETURN(const auto material,
                     OptionalMaterialFromProto(request->has_material(), request->material(), "material"));
    ASSIGN_OR_RETURN(auto set, context_.registry.catalogue().SetObjectMaterial(request->scene_id(),
                                                                               request->object_id(), material));
    ToProto(set.first, response->mutable_object());
    response->set_revision(set.second);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::RemoveObject(grpc::CallbackServerContext* ctx,
                                                     const v1::RemoveObjectRequest* request,
                                                     v1::RemoveObjectResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "RemoveObject", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    RETURN_IF_ERROR(RequireId(request->object_id(), "object_id"));
    ASSIGN_OR_RETURN(uint64_t revision,
                     context_.registry.catalogue().RemoveObject(request->scene_id(), request->object_id()));
    response->set_revision(revision);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::SetRotaryTable(grpc::CallbackServerContext* ctx,
                                                       const v1::SetRotaryTableRequest* request,
                                                       v1::SetRotaryTableResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "SetRotaryTable", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    if (!request->has_table()) return InvalidArgument("table: required");
    ASSIGN_OR_RETURN(store::TableRecord table, TableFromProto(request->table()));
    ASSIGN_OR_RETURN(uint64_t revision, context_.registry.catalogue().SetTable(request->scene_id(), table));
    ToProto(table, response->mutable_table());
    response->set_revision(revision);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* SceneService::ListMaterialPresets(grpc::CallbackServerContext* ctx,
                                                            const v1::ListMaterialPresetsRequest*,
                                                            v1::ListMaterialPresetsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListMaterialPresets", [&]() -> Status {
    for (const sensor::MaterialPreset& preset : sensor::MaterialPresets()) {
      v1::MaterialPreset* out = response->add_presets();
      out->set_name(preset.name);
      out->set_description(preset.description);
      v1::MaterialValues* values = out->mutable_values();
      values->set_diffuse_albedo(preset.material.albedo);
      values->set_metallic(preset.material.metallic);
      values->set_roughness(preset.material.roughness);
      values->set_specular_reflectance(preset.material.specular_reflectance);
    }
    return Status::Ok();
  });
}

}  // namespace vscan::api
