#include "web/web_encode.h"

#include <bit>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "vscan/common/json_quote.h"

namespace vscan::web {
namespace {

static_assert(std::endian::native == std::endian::little, "the mesh layout is written as the host stores it");

void AppendString(std::string& out, const std::string& text) { out += JsonQuote(text); }

void AppendNumber(std::string& out, double value) {
  out += std::isfinite(value) ? fmt::format("{}", value) : "null";
}

void AppendMaterial(std::string& out, const std::string& preset, const sensor::Material& material) {
  out += "{\"preset\":";
  AppendString(out, preset);
  out += ",\"albedo\":";
  AppendNumber(out, material.albedo);
  out += ",\"metallic\":";
  AppendNumber(out, material.metallic);
  out += ",\"roughness\":";
  AppendNumber(out, material.roughness);
  out += ",\"specular_reflectance\":";
  AppendNumber(out, material.specular_reflectance);
  out += '}';
}

void AppendVector(std::string& out, const Eigen::Vector3d& v) {
  out += '[';
  for (int k = 0; k < 3; ++k) {
    if (k) out += ',';
    AppendNumber(out, v[k]);
  }
  out += ']';
}

void AppendMatrix(std::string& out, const Eigen::Matrix4d& m) {
  out += '[';
  for (int r = 0; r < 4; ++r) {
    out += r ? ",[" : "[";
    for (int c = 0; c < 4; ++c) {
      if (c) out += ',';
      AppendNumber(out, m(r, c));
    }
    out += ']';
  }
  out += ']';
}

template <typename T>
void AppendRaw(std::string& out, const T& value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace

std::string ScenesJson(const std::vector<store::SceneRecord>& scenes) {
  std::string out = "{\"scenes\":[";
  for (size_t i = 0; i < scenes.size(); ++i) {
    if (i) out += ',';
    out += "{\"scene_id\":";
    AppendString(out, scenes[i].scene_id);
    out += ",\"name\":";
    AppendString(out, scenes[i].name);
    out += fmt::format(",\"revision\":{},\"object_count\":{}}}", scenes[i].revision, scenes[i].objects.size());
  }
  out += "]}";
  return out;
}

std::string SceneJson(const store::SceneRecord& scene, const std::vector<PlacedObject>& objects,
                      const std::vector<store::MountRecord>& mounts) {
  std::string out = "{\"scene_id\":";
  AppendString(out, scene.scene_id);
  out += ",\"name\":";
  AppendString(out, scene.name);
  out += fmt::format(",\"revision\":{},\"table\":{{\"enabled\":{},\"angle_deg\":", scene.revision,
                     scene.table.enabled);
  AppendNumber(out, scene.table.angle_deg);
  out += ",\"centre\":";
  AppendVector(out, scene.table.centre);
  out += ",\"axis\":";
  AppendVector(out, scene.table.axis);
  out += "},\"mounts\":[";
  for (size_t i = 0; i < mounts.size(); ++i) {
    out += i ? "," : "";
    out += "{\"mount_id\":";
    AppendString(out, mounts[i].mount_id);
    out += ",\"robot_id\":";
    AppendString(out, mounts[i].robot_id);
    out += '}';
  }
  out += "],\"objects\":[";
  for (size_t i = 0; i < objects.size(); ++i) {
    const store::ObjectRecord& object = objects[i].object;
    if (i) out += ',';
    out += "{\"object_id\":";
    AppendString(out, object.object_id);
    out += ",\"label\":";
    AppendString(out, object.label);
    out += ",\"mesh_id\":";
    AppendString(out, object.mesh_id);
    out += fmt::format(",\"instance_id\":{},\"on_table\":{},\"scale\":", object.instance_id, object.on_table);
    AppendNumber(out, object.scale);
    out += ",\"world_from_object\":";
    AppendMatrix(out, objects[i].world_from_object);
    out += ",\"material\":";
    AppendMaterial(out, objects[i].material_preset, objects[i].material);
    out += '}';
  }
  out += "]}";
  return out;
}

std::string MountJson(const MountPose& pose, const std::vector<MountShape>& shapes) {
  std::string out = "{\"mount_id\":";
  AppendString(out, pose.mount.mount_id);
  out += ",\"robot_id\":";
  AppendString(out, pose.mount.robot_id);
  out += ",\"scene_id\":";
  AppendString(out, pose.mount.scene_id);
  out += ",\"joints\":[";
  for (Eigen::Index i = 0; i < pose.joints.size(); ++i) {
    out += i ? "," : "";
    AppendNumber(out, pose.joints[i]);
  }
  out += "],\"world_from_base\":";
  AppendMatrix(out, pose.mount.base_pose);
  out += ",\"world_from_sensor\":";
  AppendMatrix(out, pose.world_from_sensor);
  out += ",\"shapes\":[";
  for (size_t i = 0; i < shapes.size(); ++i) {
    out += i ? ",{\"link\":" : "{\"link\":";
    AppendString(out, shapes[i].link);
    out += fmt::format(",\"triangles\":{},\"world_from_shape\":", shapes[i].mesh->triangles.size());
    AppendMatrix(out, shapes[i].world_from_shape);
    out += '}';
  }
  out += "]}";
  return out;
}

std::string MeshBinary(const TriangleMesh& mesh) {
  std::string out;
  out.reserve(16 + mesh.vertices.size() * 12 + mesh.triangles.size() * 12);
  out.append(kMeshMagic, sizeof(kMeshMagic));
  AppendRaw(out, kMeshLayoutVersion);
  AppendRaw(out, static_cast<uint32_t>(mesh.vertices.size()));
  AppendRaw(out, static_cast<uint32_t>(mesh.triangles.size()));
  for (const Eigen::Vector3f& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) AppendRaw(out, v[k]);
  }
  for (const auto& t : mesh.triangles) {
    for (const uint32_t index : t) AppendRaw(out, index);
  }
  return out;
}

}  // namespace vscan::web
