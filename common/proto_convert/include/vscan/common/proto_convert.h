#pragma once
// Wire types <-> native types. Every parser names the field it rejects.

#include <string_view>

#include <google/protobuf/repeated_field.h>

#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/scan.pb.h"

namespace vscan {

Eigen::Vector3d FromProto(const v1::Vector3& v);
v1::Vector3 ToProto(const Eigen::Vector3d& v);

// Accepts matrix, quaternion or look_at; an unset pose is INVALID_ARGUMENT naming field.
StatusOr<Pose3> PoseFromProto(const v1::Pose& pose, std::string_view field);
StatusOr<Pose3> PoseFromProto(const v1::Matrix4& matrix, std::string_view field);
void ToProto(const Pose3& pose, v1::Matrix4* out);
v1::Pose PoseToProto(const Pose3& pose);

// Point field list -> PointFields bit set (empty list -> kFieldsDefault).
StatusOr<uint32_t> FieldsFromProto(const google::protobuf::RepeatedField<int>& fields, std::string_view field);
void FieldsToProto(uint32_t fields, google::protobuf::RepeatedField<int>* out);

// Length unit -> metres per unit; 0 for unspecified or unknown.
double MetresPerUnit(v1::LengthUnit unit);
// The unit of a short name (m, cm, mm, in, ft); LENGTH_UNIT_UNSPECIFIED for any other.
v1::LengthUnit LengthUnitNamed(std::string_view name);

}  // namespace vscan
