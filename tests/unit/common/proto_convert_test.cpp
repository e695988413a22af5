#include "vscan/common/proto_convert.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace vscan {
namespace {

void ExpectInvalidNaming(const Status& s, const std::string& field) {
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.ToString();
  EXPECT_NE(s.message().find(field), std::string::npos) << "message should name " << field << ": " << s.message();
}

v1::Pose MatrixPose(const Eigen::Matrix4d& m) {
  v1::Pose pose;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) pose.mutable_matrix()->add_values(m(r, c));
  return pose;
}

TEST(ProtoConvert, MatrixRoundTrip) {
  Pose3 p = Pose3::Identity();
  p.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  p.translation() = Eigen::Vector3d(0.1, -2, 3);
  const auto back = PoseFromProto(PoseToProto(p), "pose");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_TRUE(back->isApprox(p, 1e-12));
}

TEST(ProtoConvert, MatrixIsRowMajor) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 3) = 5;
  const v1::Pose pose = MatrixPose(m);
  EXPECT_EQ(pose.matrix().values(3), 5);
  const auto back = PoseFromProto(pose, "pose");
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->translation().x(), 5);
}

TEST(ProtoConvert, UnsetPoseNamesField) {
  ExpectInvalidNaming(PoseFromProto(v1::Pose(), "request.pose").status(), "request.pose");
}

TEST(ProtoConvert, WrongValueCountNamesField) {
  v1::Pose pose;
  for (int i = 0; i < 12; ++i) pose.mutable_matrix()->add_values(0);
  const Status s = PoseFromProto(pose, "object.pose").status();
  ExpectInvalidNaming(s, "object.pose.matrix");
  EXPECT_NE(s.message().find("12"), std::string::npos);
}

TEST(ProtoConvert, NaNMatrixIsRejected) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(1, 3) = std::numeric_limits<double>::quiet_NaN();
  ExpectInvalidNaming(PoseFromProto(MatrixPose(m), "pose").status(), "pose.matrix");
}

TEST(ProtoConvert, NonRigidMatricesAreRejected) {
  Eigen::Matrix4d scaled = Eigen::Matrix4d::Identity();
  scaled(0, 0) = 2;
  ExpectInvalidNaming(PoseFromProto(MatrixPose(scaled), "pose").status(), "pose.matrix");

  Eigen::Matrix4d sheared = Eigen::Matrix4d::Identity();
  sheared(0, 1) = 0.3;
  ExpectInvalidNaming(PoseFromProto(MatrixPose(sheared), "pose").status(), "pose.matrix");

  Eigen::Matrix4d mirrored = Eigen::Matrix4d::Identity();
  mirrored(2, 2) = -1;
  ExpectInvalidNaming(PoseFromProto(MatrixPose(mirrored), "pose").status(), "pose.matrix");

  Eigen::Matrix4d projective = Eigen::Matrix4d::Identity();
  projective(3, 0) = 0.5;
  ExpectInvalidNaming(PoseFromProto(MatrixPose(projective), "pose").status(), "pose.matrix");
}

TEST(ProtoConvert, QuaternionPose) {
  v1::Pose pose;
  auto* q = pose.mutable_quaternion();
  *q->mutable_translation() = ToProto(Eigen::Vector3d(1, 2, 3));
  const double h = std::sqrt(0.5);
  q->set_qw(h);
  q->set_qz(h);
  const auto p = PoseFromProto(pose, "pose");
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  EXPECT_TRUE((p->linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_EQ(p->translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(ProtoConvert, QuaternionNotUnitNamesField) {
  v1::Pose pose;
  pose.mutable_quaternion()->set_qw(2);
  ExpectInvalidNaming(PoseFromProto(pose, "object.pose").status(), "object.pose.quaternion");
  v1::Pose zero;
  zero.mutable_quaternion();
  ExpectInvalidNaming(PoseFromProto(zero, "object.pose").status(), "object.pose.quaternion");
}

TEST(ProtoConvert, QuaternionNaNTranslationNamesField) {
  v1::Pose pose;
  pose.mutable_quaternion()->set_qw(1);
  pose.mutable_quaternion()->mutable_translation()->set_y(std::nan(""));
  ExpectInvalidNaming(PoseFromProto(pose, "pose").status(), "pose.quaternion.translation");
}

TEST(ProtoConvert, LookAt) {
  v1::Pose pose;
  auto* l = pose.mutable_look_at();
  *l->mutable_eye() = ToProto(Eigen::Vector3d(1, 0, 0));
  *l->mutable_target() = ToProto(Eigen::Vector3d(0, 0, 0));
  const auto p = PoseFromProto(pose, "pose");  // up defaults to +Z
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  EXPECT_TRUE(p->linear().col(2).isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_TRUE(p->linear().col(1).isApprox(Eigen::Vector3d(0, 0, -1)));  // y down
  EXPECT_NEAR(p->linear().determinant(), 1.0, 1e-12);
}

TEST(ProtoConvert, LookAtCoincidentEyeAndTarget) {
  v1::Pose pose;
  auto* l = pose.mutable_look_at();
  *l->mutable_eye() = ToProto(Eigen::Vector3d(1, 2, 3));
  *l->mutable_target() = ToProto(Eigen::Vector3d(1, 2, 3));
  ExpectInvalidNaming(PoseFromProto(pose, "request.pose").status(), "request.pose.look_at");
}

TEST(ProtoConvert, LookAtUpParallelToViewNamesUp) {
  v1::Pose pose;
  auto* l = pose.mutable_look_at();
  *l->mutable_eye() = ToProto(Eigen::Vector3d(0, 0, 2));
  *l->mutable_up() = ToProto(Eigen::Vector3d(0, 0, 1));
  ExpectInvalidNaming(PoseFromProto(pose, "pose").status(), "pose.look_at.up");
}

TEST(ProtoConvert, Fields) {
  google::protobuf::RepeatedField<int> none;
  EXPECT_EQ(*FieldsFromProto(none, "fields"), static_cast<uint32_t>(kFieldsDefault));
  google::protobuf::RepeatedField<int> out;
  FieldsToProto(kFieldsAll, &out);
  EXPECT_EQ(out.size(), 6);
  EXPECT_EQ(*FieldsFromProto(out, "fields"), static_cast<uint32_t>(kFieldsAll));
  google::protobuf::RepeatedField<int> bad;
  bad.Add(99);
  ExpectInvalidNaming(FieldsFromProto(bad, "request.fields").status(), "request.fields");
}

TEST(ProtoConvert, Units) {
  EXPECT_EQ(MetresPerUnit(v1::LENGTH_UNIT_MILLIMETRE), 0.001);
  EXPECT_EQ(MetresPerUnit(v1::LENGTH_UNIT_INCH), 0.0254);
  EXPECT_EQ(MetresPerUnit(v1::LENGTH_UNIT_UNSPECIFIED), 0.0);
}

}  // namespace
}  // namespace vscan
