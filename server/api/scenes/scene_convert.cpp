#include "api/scenes/scene_convert.h"

#include "api/job/job_convert.h"
#include "api/scenes/material_convert.h"
#include "api/transport/stored_enum_convert.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {

void ToProto(const store::TableRecord& table, v1::RotaryTable* out) {
  out->set_enabled(table.enabled);
  *out->mutable_centre() = vscan::ToProto(table.centre);
  *out->mutable_axis() = vscan::ToProto(table.axis);
  out->set_angle_deg(table.angle_deg);
}

void ToProto(const store::ObjectRecord& object, v1::SceneObject* out) {
  out->set_object_id(object.object_id);
  out->set_mesh_id(object.mesh_id);
  out->set_label(object.label);
  vscan::ToProto(Pose3(object.pose), out->mutable_pose()->mutable_matrix());
  out->set_scale(object.scale);
  out->set_on_table(object.on_table);
  out->set_instance_id(object.instance_id);
  if (object.material) ToProto(*object.material, out->mutable_material());
}

void ToProto(const store::SceneRecord& scene, v1::Scene* out) {
  out->set_scene_id(scene.scene_id);
  out->set_name(scene.name);
  out->set_revision(scene.revision);
  for (const auto& object : scene.objects) ToProto(object, out->add_objects());
  ToProto(scene.table, out->mutable_table());
  SetTime(scene.create_time_ms, out->mutable_create_time());
  SetTime(scene.update_time_ms, out->mutable_update_time());
}

void ToProto(const store::MeshRecord& mesh, v1::Mesh* out) {
  out->set_mesh_id(mesh.mesh_id);
  out->set_name(mesh.name);
  out->set_sha256(mesh.sha256);
  out->set_vertex_count(mesh.vertex_count);
  out->set_triangle_count(mesh.triangle_count);
  *out->mutable_bounds()->mutable_min() = vscan::ToProto(mesh.bounds_min);
  *out->mutable_bounds()->mutable_max() = vscan::ToProto(mesh.bounds_max);
  out->set_source_unit(*kLengthUnits.Forward(mesh.source_unit));
  out->set_source_scale(mesh.source_scale);
  SetTime(mesh.create_time_ms, out->mutable_create_time());
  if (mesh.material) ToProto(*mesh.material, out->mutable_material());
}

}  // namespace vscan::api
