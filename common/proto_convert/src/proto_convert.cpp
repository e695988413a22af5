#include "vscan/common/proto_convert.h"

#include <string>

namespace vscan {

static_assert(static_cast<int>(PointStatus::kMeasured) == v1::POINT_STATUS_MEASURED);
static_assert(static_cast<int>(PointStatus::kFlyingPixel) == v1::POINT_STATUS_FLYING_PIXEL);
static_assert(static_cast<int>(PointStatus::kRejectedUnlit) == v1::POINT_STATUS_REJECTED_UNLIT);
static_assert(static_cast<int>(PointStatus::kRejectedDark) == v1::POINT_STATUS_REJECTED_DARK);
static_assert(static_cast<int>(PointStatus::kRejectedSaturated) == v1::POINT_STATUS_REJECTED_SATURATED);
static_assert(static_cast<int>(PointStatus::kRejectedInterreflection) == v1::POINT_STATUS_REJECTED_INTERREFLECTION);

Eigen::Vector3d FromProto(const v1::Vector3& v) { return {v.x(), v.y(), v.z()}; }

v1::Vector3 ToProto(const Eigen::Vector3d& v) {
  v1::Vector3 out;
  out.set_x(v.x());
  out.set_y(v.y());
  out.set_z(v.z());
  return out;
}

StatusOr<Pose3> PoseFromProto(const v1::Matrix4& matrix, std::string_view field) {
  if (matrix.values_size() != 16) {
    return InvalidArgument(std::string(field) + ".values: need 16 values (row-major 4x4), got " +
                           std::to_string(matrix.values_size()));
  }
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = matrix.values(r * 4 + c);
  return PoseFromMatrix(m, field);
}

StatusOr<Pose3> PoseFromProto(const v1::Pose& pose, std::string_view field) {
  const std::string f(field);
  switch (pose.kind_case()) {
    case v1::Pose::kMatrix:
      return PoseFromProto(pose.matrix(), f + ".matrix");
    case v1::Pose::kQuaternion: {
      const auto& q = pose.quaternion();
      return PoseFromQuaternion(FromProto(q.translation()), Eigen::Quaterniond(q.qw(), q.qx(), q.qy(), q.qz()),
                                f + ".quaternion");
    }
    case v1::Pose::kLookAt: {
      const auto& l = pose.look_at();
      Eigen::Vector3d up = FromProto(l.up());
      if (!l.has_up()) up = Eigen::Vector3d::UnitZ();
      return PoseFromLookAt(FromProto(l.eye()), FromProto(l.target()), up, f + ".look_at");
    }
    case v1::Pose::KIND_NOT_SET:
      break;
  }
  return InvalidArgument(f + ": required (matrix, quaternion or look_at)");
}

void ToProto(const Pose3& pose, v1::Matrix4* out) {
  out->clear_values();
  const Eigen::Matrix4d m = pose.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out->add_values(m(r, c));
}

v1::Pose PoseToProto(const Pose3& pose) {
  v1::Pose out;
  ToProto(pose, out.mutable_matrix());
  return out;
}

StatusOr<uint32_t> FieldsFromProto(const google::protobuf::RepeatedField<int>& fields, std::string_view field) {
  if (fields.empty()) return static_cast<uint32_t>(kFieldsDefault);
  uint32_t out = kFieldPosition;
  for (int f : fields) {
    switch (f) {
      case v1::POINT_FIELD_POSITION: out |= kFieldPosition; break;
      case v1::POINT_FIELD_NORMAL: out |= kFieldNormal; break;
      case v1::POINT_FIELD_RANGE: out |= kFieldRange; break;
      case v1::POINT_FIELD_INTENSITY: out |= kFieldIntensity; break;
      case v1::POINT_FIELD_INSTANCE_ID: out |= kFieldInstanceId; break;
      case v1::POINT_FIELD_PIXEL: out |= kFieldPixel; break;
      case v1::POINT_FIELD_CLEAN_POSITION: out |= kFieldCleanPosition; break;
      case v1::POINT_FIELD_INCIDENCE_ANGLE: out |= kFieldIncidence; break;
      case v1::POINT_FIELD_STATUS: out |= kFieldStatus; break;
      case v1::POINT_FIELD_ESTIMATED_NORMAL: out |= kFieldEstimatedNormal; break;
      default:
        return InvalidArgument(std::string(field) + ": unknown point field " + std::to_string(f));
    }
  }
  return out;
}

void FieldsToProto(uint32_t fields, google::protobuf::RepeatedField<int>* out) {
  out->Clear();
  if (fields & kFieldPosition) out->Add(v1::POINT_FIELD_POSITION);
  if (fields & kFieldNormal) out->Add(v1::POINT_FIELD_NORMAL);
  if (fields & kFieldRange) out->Add(v1::POINT_FIELD_RANGE);
  if (fields & kFieldIntensity) out->Add(v1::POINT_FIELD_INTENSITY);
  if (fields & kFieldInstanceId) out->Add(v1::POINT_FIELD_INSTANCE_ID);
  if (fields & kFieldPixel) out->Add(v1::POINT_FIELD_PIXEL);
  if (fields & kFieldCleanPosition) out->Add(v1::POINT_FIELD_CLEAN_POSITION);
  if (fields & kFieldIncidence) out->Add(v1::POINT_FIELD_INCIDENCE_ANGLE);
  if (fields & kFieldStatus) out->Add(v1::POINT_FIELD_STATUS);
  if (fields & kFieldEstimatedNormal) out->Add(v1::POINT_FIELD_ESTIMATED_NORMAL);
}

double MetresPerUnit(v1::LengthUnit unit) {
  switch (unit) {
    case v1::LENGTH_UNIT_METRE: return 1.0;
    case v1::LENGTH_UNIT_CENTIMETRE: return 0.01;
    case v1::LENGTH_UNIT_MILLIMETRE: return 0.001;
    case v1::LENGTH_UNIT_INCH: return 0.0254;
    case v1::LENGTH_UNIT_FOOT: return 0.3048;
    default: return 0.0;
  }
}

v1::LengthUnit LengthUnitNamed(std::string_view name) {
  if (name == "m") return v1::LENGTH_UNIT_METRE;
  if (name == "cm") return v1::LENGTH_UNIT_CENTIMETRE;
  if (name == "mm") return v1::LENGTH_UNIT_MILLIMETRE;
  if (name == "in") return v1::LENGTH_UNIT_INCH;
  if (name == "ft") return v1::LENGTH_UNIT_FOOT;
  return v1::LENGTH_UNIT_UNSPECIFIED;
}

}  // namespace vscan
