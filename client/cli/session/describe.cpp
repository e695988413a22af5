#include "session/describe.h"

#include <cstdio>

#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

// The names `vscan scan --fields` takes.
const char* FieldName(int field) {
  switch (field) {
    case v1::POINT_FIELD_POSITION: return "position";
    case v1::POINT_FIELD_NORMAL: return "normal";
    case v1::POINT_FIELD_RANGE: return "range";
    case v1::POINT_FIELD_INTENSITY: return "intensity";
    case v1::POINT_FIELD_INSTANCE_ID: return "instance";
    case v1::POINT_FIELD_PIXEL: return "pixel";
    case v1::POINT_FIELD_CLEAN_POSITION: return "clean";
    case v1::POINT_FIELD_INCIDENCE_ANGLE: return "incidence";
    case v1::POINT_FIELD_STATUS: return "status";
    case v1::POINT_FIELD_ESTIMATED_NORMAL: return "estimated-normal";
    default: return "?";
  }
}

}  // namespace

std::string Describe(const v1::Vector3& v) {
  // Appended piecewise: GCC 12 at -O3 warns (-Wrestrict) on "literal" + std::string chains here.
  std::string out = "(";
  out.append(Num(v.x())).append(", ").append(Num(v.y())).append(", ").append(Num(v.z())).append(")");
  return out;
}

std::string Describe(const v1::Pose& pose) {
  if (pose.kind_case() == v1::Pose::KIND_NOT_SET) return "identity";
  const auto parsed = PoseFromProto(pose, "pose");
  if (!parsed.ok()) return "invalid pose";
  const Eigen::Quaterniond q(parsed->linear());
  return "t=" + Describe(ToProto(Eigen::Vector3d(parsed->translation()))) + " q(wxyz)=(" + Num(q.w()) + ", " +
         Num(q.x()) + ", " + Num(q.y()) + ", " + Num(q.z()) + ")";
}

std::string Describe(const v1::RotaryTable& table) {
  return std::string(table.enabled() ? "enabled" : "disabled") + ", centre " + Describe(table.centre()) + ", axis " +
         Describe(table.axis()) + ", angle " + Num(table.angle_deg()) + " deg";
}

std::string Describe(const v1::Material& material) {
  if (!material.preset().empty()) return material.preset();
  const v1::MaterialValues& v = material.values();
  return "albedo " + Num(v.diffuse_albedo()) + " metallic " + Num(v.metallic()) + " roughness " + Num(v.roughness()) +
         " specular " + Num(v.specular_reflectance());
}

std::string Describe(const v1::SceneObject& object) {
  std::string out = object.object_id() + "  mesh " + object.mesh_id() + "  instance " +
                    std::to_string(object.instance_id()) + "  scale " + Num(object.scale()) + "  " +
                    Describe(object.pose());
  if (object.on_table()) out += "  on table";
  if (!object.label().empty()) out += "  label '" + object.label() + "'";
  if (object.has_material()) out += "  material " + Describe(object.material());
  return out;
}

std::string Describe(const v1::Mesh& mesh) {
  return mesh.mesh_id() + "  " + mesh.name() + "  " + std::to_string(mesh.vertex_count()) + " vertices, " +
         std::to_string(mesh.triangle_count()) + " triangles, bounds " + Describe(mesh.bounds().min()) + " .. " +
         Describe(mesh.bounds().max()) + " m (source " + UnitName(mesh.source_unit()) + " x" +
         Num(mesh.source_scale()) + ")" + (mesh.has_material() ? "  material " + Describe(mesh.material()) : "");
}

std::string Describe(const v1::Cloud& cloud) {
  std::string out = cloud.cloud_id() + "  " + cloud.name() + "  " + std::to_string(cloud.points()) + " points (";
  for (int i = 0; i < cloud.fields_size(); ++i) out.append(i ? "," : "").append(FieldName(cloud.fields(i)));
  out += ")  ";
  out += cloud.origin() == v1::CLOUD_ORIGIN_CAMPAIGN_SCAN ? "scan of " + cloud.job_id() : std::string("uploaded");
  if (!cloud.scene_id().empty()) out += "  scene " + cloud.scene_id();
  out += cloud.frame() == v1::FRAME_SENSOR ? "  sensor frame" : "  world frame";
  if (cloud.has_sensor_pose()) {
    v1::Pose pose;
    *pose.mutable_matrix() = cloud.sensor_pose();
    out += "  sensor " + Describe(pose);
  }
  if (cloud.has_table_angle_deg()) out += "  table " + Num(cloud.table_angle_deg()) + " deg";
  out += "  " + std::to_string(cloud.size_bytes()) + " bytes";
  return out;
}

std::string UnitName(v1::LengthUnit unit) {
  switch (unit) {
    case v1::LENGTH_UNIT_METRE: return "m";
    case v1::LENGTH_UNIT_CENTIMETRE: return "cm";
    case v1::LENGTH_UNIT_MILLIMETRE: return "mm";
    case v1::LENGTH_UNIT_INCH: return "in";
    case v1::LENGTH_UNIT_FOOT: return "ft";
    default: return "?";
  }
}

}  // namespace vscan::cli
