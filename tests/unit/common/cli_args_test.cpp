#include "args.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vscan/common/chunk_limits.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

void ExpectInvalidNaming(const Status& s, const std::string& option) {
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.ToString();
  EXPECT_NE(s.message().find(option), std::string::npos) << s.message();
}

TEST(CliArgs, Vector3) {
  const auto v = ParseVector3("1, -2.5,3e-1", "--position");
  ASSERT_TRUE(v.ok()) << v.status().ToString();
  EXPECT_EQ(*v, Eigen::Vector3d(1, -2.5, 0.3));
  ExpectInvalidNaming(ParseVector3("1,2", "--position").status(), "--position");
  ExpectInvalidNaming(ParseVector3("1,2,3,4", "--eye").status(), "--eye");
  ExpectInvalidNaming(ParseVector3("1,x,3", "--eye").status(), "--eye");
  ExpectInvalidNaming(ParseVector3("1,,3", "--eye").status(), "--eye");
  ExpectInvalidNaming(ParseVector3("1,nan,3", "--eye").status(), "--eye");
  ExpectInvalidNaming(ParseVector3("1,inf,3", "--eye").status(), "--eye");
  ExpectInvalidNaming(ParseVector3("1,2,3abc", "--eye").status(), "--eye");
}

TEST(CliArgs, Numbers) {
  const auto v = ParseNumbers("1,2,3,4", 4, "--quat");
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(v->size(), 4u);
  ExpectInvalidNaming(ParseNumbers("", 1, "--x").status(), "--x");
}

TEST(CliArgs, Units) {
  EXPECT_EQ(*ParseUnit("mm"), v1::LENGTH_UNIT_MILLIMETRE);
  EXPECT_EQ(*ParseUnit("M"), v1::LENGTH_UNIT_METRE);
  EXPECT_EQ(*ParseUnit("in"), v1::LENGTH_UNIT_INCH);
  EXPECT_EQ(*ParseUnit("ft"), v1::LENGTH_UNIT_FOOT);
  EXPECT_EQ(*ParseUnit("cm"), v1::LENGTH_UNIT_CENTIMETRE);
  ExpectInvalidNaming(ParseUnit("furlong").status(), "--unit");
}

TEST(CliArgs, MeshFormats) {
  EXPECT_EQ(*ParseMeshFormat("STL"), v1::MESH_FORMAT_STL);
  ExpectInvalidNaming(ParseMeshFormat("off").status(), "--format");
}

TEST(CliArgs, Fields) {
  const auto f = ParseFields("normal,range,instance");
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(*f, (std::vector<v1::PointField>{v1::POINT_FIELD_POSITION, v1::POINT_FIELD_NORMAL,
                                              v1::POINT_FIELD_RANGE, v1::POINT_FIELD_INSTANCE_ID}));
  EXPECT_EQ(ParseFields("all")->size(), 6u);
  EXPECT_EQ(ParseFields("position,position")->size(), 1u);
  ExpectInvalidNaming(ParseFields("position,colour").status(), "--fields");
}

TEST(CliArgs, FrameAndBackend) {
  EXPECT_EQ(*ParseFrame("sensor"), v1::FRAME_SENSOR);
  ExpectInvalidNaming(ParseFrame("camera").status(), "--frame");
  EXPECT_EQ(*ParseBackend("depth"), v1::SCAN_BACKEND_RASTER_DEPTH);
  ExpectInvalidNaming(ParseBackend("magic").status(), "--backend");
}

TEST(CliArgs, RpyIsZYX) {
  const Eigen::Matrix3d r = RotationFromRpyDegrees(90, 0, 90);
  // Rx(90) sends y to z; then Rz(90) leaves z alone.
  EXPECT_TRUE((r * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  // Rx leaves x alone; Rz(90) sends it to y.
  EXPECT_TRUE((r * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST(CliArgs, PoseArgs) {
  PoseArgs args;
  args.position = "1,2,3";
  args.quat = "0.7071067811865476,0,0,0.7071067811865476";
  const auto parts = ParsePoseArgs(args);
  ASSERT_TRUE(parts.ok()) << parts.status().ToString();
  ASSERT_TRUE(parts->complete());
  const Pose3 p = ApplyPoseParts(*parts, Pose3::Identity());
  EXPECT_TRUE((p.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));
  EXPECT_EQ(p.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(CliArgs, PartialPoseKeepsTheRest) {
  PoseArgs args;
  args.rpy = "0,0,180";
  const auto parts = ParsePoseArgs(args);
  ASSERT_TRUE(parts.ok());
  EXPECT_FALSE(parts->complete());
  Pose3 base = Pose3::Identity();
  base.translation() = Eigen::Vector3d(4, 5, 6);
  const Pose3 p = ApplyPoseParts(*parts, base);
  EXPECT_EQ(p.translation(), Eigen::Vector3d(4, 5, 6));
  EXPECT_TRUE((p.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE(ParsePoseArgs(PoseArgs{})->empty());
}

TEST(CliArgs, PoseArgsRejections) {
  PoseArgs not_unit;
  not_unit.quat = "1,1,0,0";
  ExpectInvalidNaming(ParsePoseArgs(not_unit).status(), "--quat");

  PoseArgs short_matrix;
  short_matrix.matrix = "1,0,0,0, 0,1,0,0, 0,0,1,0";
  ExpectInvalidNaming(ParsePoseArgs(short_matrix).status(), "--matrix");

  PoseArgs scaled;
  scaled.matrix = "2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1";
  ExpectInvalidNaming(ParsePoseArgs(scaled).status(), "--matrix");

  PoseArgs both;
  both.rpy = "0,0,0";
  both.quat = "1,0,0,0";
  EXPECT_EQ(ParsePoseArgs(both).status().code(), StatusCode::kInvalidArgument);
}

TEST(CliArgs, MatrixPoseIsRowMajor) {
  PoseArgs args;
  args.matrix = "0,-1,0,1, 1,0,0,2, 0,0,1,3, 0,0,0,1";
  const auto parts = ParsePoseArgs(args);
  ASSERT_TRUE(parts.ok()) << parts.status().ToString();
  const Pose3 p = ApplyPoseParts(*parts, Pose3::Identity());
  EXPECT_EQ(p.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE((p.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST(CliArgs, ScanRequestDefaults) {
  ScanArgs args;
  args.scene_id = "s1";
  args.eye = "1,0,0.5";
  args.target = "0,0,0";
  const auto request = BuildScanRequest(args);
  ASSERT_TRUE(request.ok()) << request.status().ToString();
  EXPECT_EQ(request->scene_id(), "s1");
  const auto& cam = request->sensor().pinhole();
  EXPECT_EQ(cam.width(), 640u);
  EXPECT_EQ(cam.height(), 480u);
  EXPECT_EQ(cam.horizontal_fov_deg(), 60.0);
  EXPECT_EQ(cam.near(), 0.05);
  EXPECT_EQ(cam.far(), 10.0);
  ASSERT_TRUE(request->pose().has_look_at());
  EXPECT_EQ(request->pose().look_at().up().z(), 1.0);
  EXPECT_EQ(request->frame(), v1::FRAME_WORLD);
  EXPECT_EQ(request->backend(), v1::SCAN_BACKEND_RAYCAST);
  EXPECT_EQ(request->fields_size(), 0);
  EXPECT_FALSE(request->has_table_angle_deg());
  EXPECT_EQ(request->chunk_bytes(), 0u);
}

TEST(CliArgs, ScanRequestOptions) {
  ScanArgs args;
  args.scene_id = "s1";
  args.pose_matrix = "1,0,0,0, 0,1,0,0, 0,0,1,-2, 0,0,0,1";
  args.intrinsics = "500,500,320,240";
  args.lighting = "1,1,0,0.5";
  args.frame = "sensor";
  args.fields = "position,pixel";
  args.table_angle_deg = 45;
  args.chunk_kib = 256;
  const auto request = BuildScanRequest(args);
  ASSERT_TRUE(request.ok()) << request.status().ToString();
  EXPECT_EQ(request->sensor().pinhole().intrinsics().fx(), 500);
  EXPECT_EQ(request->sensor().pinhole().lighting().quadratic(), 0.5);
  ASSERT_TRUE(request->pose().has_matrix());
  EXPECT_EQ(request->pose().matrix().values(11), -2);
  EXPECT_EQ(request->frame(), v1::FRAME_SENSOR);
  EXPECT_EQ(request->fields_size(), 2);
  EXPECT_EQ(request->table_angle_deg(), 45);
  EXPECT_EQ(request->chunk_bytes(), 256u * 1024u);
}

TEST(CliArgs, ScanRequestRejections) {
  ScanArgs base;
  base.scene_id = "s";
  base.eye = "1,0,0";
  base.target = "0,0,0";

  ScanArgs no_pose = base;
  no_pose.eye.clear();
  ExpectInvalidNaming(BuildScanRequest(no_pose).status(), "--eye");

  ScanArgs same = base;
  same.target = "1,0,0";
  ExpectInvalidNaming(BuildScanRequest(same).status(), "--eye/--target");

  ScanArgs zero_width = base;
  zero_width.width = 0;
  ExpectInvalidNaming(BuildScanRequest(zero_width).status(), "--width");

  ScanArgs near_far = base;
  near_far.near = 2;
  near_far.far = 1;
  ExpectInvalidNaming(BuildScanRequest(near_far).status(), "--near");

  ScanArgs chunk = base;
  chunk.chunk_kib = 1;
  ExpectInvalidNaming(BuildScanRequest(chunk).status(), "--chunk-kib");

  ScanArgs hfov = base;
  hfov.hfov_deg = 180;
  ExpectInvalidNaming(BuildScanRequest(hfov).status(), "--hfov");
}

// --chunk-kib accepts exactly the chunk sizes the server accepts.
TEST(CliArgs, ChunkKibMatchesTheServerLimits) {
  ScanArgs args;
  args.scene_id = "s";
  args.eye = "1,0,0";
  args.target = "0,0,0";
  for (const size_t bytes : {kMinChunkBytes, kDefaultChunkBytes, kMaxChunkBytes}) {
    args.chunk_kib = static_cast<uint32_t>(bytes / 1024);
    const auto request = BuildScanRequest(args);
    ASSERT_TRUE(request.ok()) << request.status().ToString();
    EXPECT_EQ(request->chunk_bytes(), bytes);
  }
  for (const size_t bytes : {kMinChunkBytes - 1024, kMaxChunkBytes + 1024}) {
    args.chunk_kib = static_cast<uint32_t>(bytes / 1024);
    const Status s = BuildScanRequest(args).status();
    ExpectInvalidNaming(s, "--chunk-kib");
    EXPECT_EQ(s.field(), "--chunk-kib");
  }
}

}  // namespace
}  // namespace vscan::cli
