#include "grid_scene_upload.h"

#include "vscan/common/proto_convert.h"

namespace vscan::bench {

StatusOr<v1::ScanRequest> UploadBunnyGrid(client::Client& client, const BunnyGrid& grid, const std::string& bunny_path,
                                          const std::string& scene_name) {
  client::MeshUploadOptions upload;
  upload.unit = v1::LENGTH_UNIT_METRE;
  ASSIGN_OR_RETURN(const v1::Mesh mesh, client.UploadMeshFile(bunny_path, upload));
  ASSIGN_OR_RETURN(const v1::Scene scene, client.CreateScene(scene_name));
  for (const auto& instance : grid.instances) {
    client::ObjectPlacement placement;
    placement.pose = PoseToProto(instance.world_from_object);
    placement.scale = instance.scale;
    RETURN_IF_ERROR(client.AddObject(scene.scene_id(), mesh.mesh_id(), placement).status());
  }
  v1::ScanRequest request;
  request.set_scene_id(scene.scene_id());
  auto* pinhole = request.mutable_sensor()->mutable_pinhole();
  pinhole->set_width(grid.camera.width);
  pinhole->set_height(grid.camera.height);
  auto* k = pinhole->mutable_intrinsics();
  k->set_fx(grid.camera.fx);
  k->set_fy(grid.camera.fy);
  k->set_cx(grid.camera.cx);
  k->set_cy(grid.camera.cy);
  pinhole->set_near(grid.camera.near);
  pinhole->set_far(grid.camera.far);
  *request.mutable_pose() = PoseToProto(grid.world_from_sensor);
  return request;
}

}  // namespace vscan::bench
