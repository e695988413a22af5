#include "web/web_encode.h"

#include <bit>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "web/web_bytes.h"
#include "web/web_json.h"

namespace vscan::web {
namespace {

void AppendMaterial(std::string& out, const std::string& preset, const sensor::Material& material) {
  out += "{\"preset\":";
  AppendJsonString(out, preset);
  out += ",\"albedo\":";
  AppendJsonNumber(out, material.albedo);
  out += ",\"metallic\":";
  AppendJsonNumber(out, material.metallic);
  out += ",\"roughness\":";
  AppendJsonNumber(out, material.roughness);
  out += ",\"specular_reflectance\":";
  AppendJsonNumber(out, material.specular_reflectance);
  out += '}';
}

}  // namespace

std::string ScenesJson(const std::vector<store::SceneRecord>& scenes) {
  std::string out = "{\"scenes\":[";
  for (size_t i = 0; i < scenes.size(); ++i) {
    if (i) out += ',';
    out += "{\"scene_id\":";
    AppendJsonString(out, scenes[i].scene_id);
    out += ",\"name\":";
    AppendJsonString(out, scenes[i].name);
    out += fmt::format(",\"revision\":{},\"object_count\":{}}}", scenes[i].revision, scenes[i].objects.size());
  }
  out += "]}";
  return out;
}

std::string SceneJson(const store::SceneRecord& scene, const std::vector<PlacedObject>& objects,
                      const std::vector<store::MountRecord>& mounts) {
  std::string out = "{\"scene_id\":";
  AppendJsonString(out, scene.scene_id);
  out += ",\"name\":";
  AppendJsonString(out, scene.name);
  out += fmt::format(",\"revision\":{},\"table\":{{\"enabled\":{},\"angle_deg\":", scene.revision,
                     scene.table.enabled);
  AppendJsonNumber(out, scene.table.angle_deg);
  out += ",\"centre\":";
  AppendJsonVector(out, scene.table.centre);
  out += ",\"axis\":";
  AppendJsonVector(out, scene.table.axis);
  out += "},\"mounts\":[";
  for (size_t i = 0; i < mounts.size(); ++i) {
    out += i ? "," : "";
    out += "{\"mount_id\":";
    AppendJsonString(out, mounts[i].mount_id);
    out += ",\"robot_id\":";
    AppendJsonString(out, mounts[i].robot_id);
    out += '}';
  }
  out += "],\"objects\":[";
  for (size_t i = 0; i < objects.size(); ++i) {
    const store::ObjectRecord& object = objects[i].object;
    if (i) out += ',';
    out += "{\"object_id\":";
    AppendJsonString(out, object.object_id);
    out += ",\"label\":";
    AppendJsonString(out, object.label);
    out += ",\"mesh_id\":";
    AppendJsonString(out, object.mesh_id);
    out += fmt::format(",\"instance_id\":{},\"on_table\":{},\"scale\":", object.instance_id, object.on_table);
    AppendJsonNumber(out, object.scale);
    out += ",\"world_from_object\":";
    AppendJsonRows(out, objects[i].world_from_object);
    out += ",\"material\":";
    AppendMaterial(out, objects[i].material_preset, objects[i].material);
    out += '}';
  }
  out += "]}";
  return out;
}

std::string MountJson(const MountPose& pose, const std::vector<MountShape>& shapes) {
  std::string out = "{\"mount_id\":";
  AppendJsonString(out, pose.mount.mount_id);
  out += ",\"robot_id\":";
  AppendJsonString(out, pose.mount.robot_id);
  out += ",\"scene_id\":";
  AppendJsonString(out, pose.mount.scene_id);
  out += ",\"joints\":[";
  for (Eigen::Index i = 0; i < pose.joints.size(); ++i) {
    out += i ? "," : "";
    AppendJsonNumber(out, pose.joints[i]);
  }
  out += "],\"world_from_base\":";
  AppendJsonRows(out, pose.mount.base_pose);
  out += ",\"world_from_sensor\":";
  AppendJsonRows(out, pose.world_from_sensor);
  out += ",\"shapes\":[";
  for (size_t i = 0; i < shapes.size(); ++i) {
    out += i ? ",{\"link\":" : "{\"link\":";
    AppendJsonString(out, shapes[i].link);
    out += fmt::format(",\"triangles\":{},\"world_from_shape\":", shapes[i].mesh->triangles.size());
    AppendJsonRows(out, shapes[i].world_from_shape);
    out += '}';
  }
  out += "]}";
  return out;
}

std::string MeshBinary(const TriangleMesh& mesh) {
  std::string out;
  out.reserve(16 + mesh.vertices.size() * 12 + mesh.triangles.size() * 12);
  out.append(kMeshMagic, sizeof(kMeshMagic));
  AppendBytesOf(out, kMeshLayoutVersion);
  AppendBytesOf(out, static_cast<uint32_t>(mesh.vertices.size()));
  AppendBytesOf(out, static_cast<uint32_t>(mesh.triangles.size()));
  for (const Eigen::Vector3f& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) AppendBytesOf(out, v[k]);
  }
  for (const auto& t : mesh.triangles) {
    for (const uint32_t index : t) AppendBytesOf(out, index);
  }
  return out;
}

}  // namespace vscan::web
