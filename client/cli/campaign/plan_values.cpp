#include "campaign/plan_values.h"

#include "session/args.h"

#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

// The rules the server applies to every pose it is sent (proto_convert), checked before upload.
StatusOr<v1::Pose> Checked(const YamlReader& yaml, const YamlAt& at, v1::Pose pose) {
  const auto checked = PoseFromProto(pose, at.path);
  if (!checked.ok()) return yaml.Error(at.node.Mark(), "", checked.status().message());
  return pose;
}

}  // namespace

StatusOr<Eigen::Vector3d> RequiredVector(const YamlReader& yaml, const YamlAt& at) {
  if (!YamlReader::Has(at)) return yaml.Error(at, "required: [x, y, z] in metres");
  return yaml.Vector3(at);
}

StatusOr<v1::Pose> ReadPlanPose(const YamlReader& yaml, const YamlAt& at) {
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"xyz", "rpy_deg", "quat", "matrix", "look_at"}));
  const YamlAt xyz = YamlReader::Child(at, "xyz");
  const YamlAt rpy = YamlReader::Child(at, "rpy_deg");
  const YamlAt quat = YamlReader::Child(at, "quat");
  const YamlAt matrix = YamlReader::Child(at, "matrix");
  const YamlAt look_at = YamlReader::Child(at, "look_at");
  const int forms = YamlReader::Has(rpy) + YamlReader::Has(quat) + YamlReader::Has(matrix) + YamlReader::Has(look_at);
  if (forms > 1) return yaml.Error(at, "give one of rpy_deg, quat, matrix, look_at");
  if (YamlReader::Has(xyz) && (YamlReader::Has(matrix) || YamlReader::Has(look_at))) {
    return yaml.Error(xyz, "matrix and look_at already hold the position");
  }
  if (YamlReader::Has(look_at)) {
    RETURN_IF_ERROR(yaml.ExpectMap(look_at, {"eye", "target", "up"}));
    ASSIGN_OR_RETURN(const Eigen::Vector3d eye, RequiredVector(yaml, YamlReader::Child(look_at, "eye")));
    ASSIGN_OR_RETURN(const Eigen::Vector3d target, RequiredVector(yaml, YamlReader::Child(look_at, "target")));
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    if (const YamlAt u = YamlReader::Child(look_at, "up"); YamlReader::Has(u)) {
      ASSIGN_OR_RETURN(up, yaml.Vector3(u));
    }
    v1::Pose pose;
    *pose.mutable_look_at()->mutable_eye() = ToProto(eye);
    *pose.mutable_look_at()->mutable_target() = ToProto(target);
    *pose.mutable_look_at()->mutable_up() = ToProto(up);
    return Checked(yaml, at, std::move(pose));
  }
  Pose3 pose = Pose3::Identity();
  if (YamlReader::Has(matrix)) {
    ASSIGN_OR_RETURN(const auto v, yaml.Numbers(matrix, 16));
    const Eigen::Matrix4d m = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(v.data());
    const auto rigid = PoseFromMatrix(m, "matrix");
    if (!rigid.ok()) return yaml.Error(matrix, "not a rigid transform (" + rigid.status().message() + ")");
    pose = *rigid;
  }
  if (YamlReader::Has(rpy)) {
    ASSIGN_OR_RETURN(const auto v, yaml.Numbers(rpy, 3));
    pose.linear() = RotationFromRpyDegrees(v[0], v[1], v[2]);
  }
  if (YamlReader::Has(quat)) {
    ASSIGN_OR_RETURN(const auto v, yaml.Numbers(quat, 4));
    const auto q = PoseFromQuaternion(Eigen::Vector3d::Zero(), Eigen::Quaterniond(v[0], v[1], v[2], v[3]), "quat");
    if (!q.ok()) return yaml.Error(quat, "expected a unit quaternion w, x, y, z");
    pose.linear() = q->linear();
  }
  if (YamlReader::Has(xyz)) {
    ASSIGN_OR_RETURN(pose.translation(), yaml.Vector3(xyz));
  }
  return Checked(yaml, at, PoseToProto(pose));
}

v1::Material MaterialMessage(const plan::MaterialPlan& material) {
  v1::Material out;
  if (!material.preset.empty()) {
    out.set_preset(material.preset);
    return out;
  }
  v1::MaterialValues* values = out.mutable_values();
  values->set_diffuse_albedo(material.diffuse_albedo);
  values->set_metallic(material.metallic);
  values->set_roughness(material.roughness);
  values->set_specular_reflectance(material.specular_reflectance);
  return out;
}

StatusOr<std::filesystem::path> ReadPlanPath(const YamlReader& yaml, const YamlAt& at,
                                             const std::filesystem::path& base_dir) {
  if (!YamlReader::Has(at)) return yaml.Error(at, "required: a path relative to the plan file");
  ASSIGN_OR_RETURN(const std::string text, yaml.String(at));
  const std::filesystem::path path = (base_dir / text).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return yaml.Error(at, "no such file or directory: " + path.string());
  return path;
}

}  // namespace vscan::cli
