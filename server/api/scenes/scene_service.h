#pragma once
// SceneService: scenes, meshes, objects and the rotary table.

#include "service/context/service_context.h"
#include "vscan/v1/scene.grpc.pb.h"

namespace vscan::api {

class SceneService final : public v1::SceneService::CallbackService {
 public:
  explicit SceneService(service::ServiceContext& context) : context_(context) {}

  grpc::ServerUnaryReactor* CreateScene(grpc::CallbackServerContext* ctx, const v1::CreateSceneRequest* request,
                                        v1::CreateSceneResponse* response) override;
  grpc::ServerUnaryReactor* GetScene(grpc::CallbackServerContext* ctx, const v1::GetSceneRequest* request,
                                     v1::GetSceneResponse* response) override;
  grpc::ServerUnaryReactor* ListScenes(grpc::CallbackServerContext* ctx, const v1::ListScenesRequest* request,
                                       v1::ListScenesResponse* response) override;
  grpc::ServerUnaryReactor* DeleteScene(grpc::CallbackServerContext* ctx, const v1::DeleteSceneRequest* request,
                                        v1::DeleteSceneResponse* response) override;
  grpc::ServerReadReactor<v1::UploadMeshRequest>* UploadMesh(grpc::CallbackServerContext* ctx,
                                                             v1::UploadMeshResponse* response) override;
  grpc::ServerUnaryReactor* GetMesh(grpc::CallbackServerContext* ctx, const v1::GetMeshRequest* request,
                                    v1::GetMeshResponse* response) override;
  grpc::ServerUnaryReactor* ListMeshes(grpc::CallbackServerContext* ctx, const v1::ListMeshesRequest* request,
                                       v1::ListMeshesResponse* response) override;
  grpc::ServerUnaryReactor* DeleteMesh(grpc::CallbackServerContext* ctx, const v1::DeleteMeshRequest* request,
                                       v1::DeleteMeshResponse* response) override;
  grpc::ServerUnaryReactor* AddObject(grpc::CallbackServerContext* ctx, const v1::AddObjectRequest* request,
                                      v1::AddObjectResponse* response) override;
  grpc::ServerUnaryReactor* MoveObject(grpc::CallbackServerContext* ctx, const v1::MoveObjectRequest* request,
                                       v1::MoveObjectResponse* response) override;
  grpc::ServerUnaryReactor* SetObjectMaterial(grpc::CallbackServerContext* ctx,
                                              const v1::SetObjectMaterialRequest* request,
                                              v1::SetObjectMaterialResponse* response) override;
  grpc::ServerUnaryReactor* RemoveObject(grpc::CallbackServerContext* ctx, const v1::RemoveObjectRequest* request,
                                         v1::RemoveObjectResponse* response) override;
  grpc::ServerUnaryReactor* SetRotaryTable(grpc::CallbackServerContext* ctx,
                                           const v1::SetRotaryTableRequest* request,
                                           v1::SetRotaryTableResponse* response) override;
  grpc::ServerUnaryReactor* ListMaterialPresets(grpc::CallbackServerContext* ctx,
                                                const v1::ListMaterialPresetsRequest* request,
                                                v1::ListMaterialPresetsResponse* response) override;

 private:
  service::ServiceContext& context_;
};

}  // namespace vscan::api
