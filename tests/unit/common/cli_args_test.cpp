#include "session/args.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "model/model_args.h"
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


// --- vscan align | reconstruct | evaluate -------------------------------------------------------

using google::protobuf::util::MessageDifferencer;

ModelArgs TwoClouds() {
  ModelArgs args;
  args.cloud_ids = {"cld_a", "cld_b"};
  return args;
}

TEST(ModelArgs, AlignMapsEveryOption) {
  ModelArgs args = TwoClouds();
  args.scene_id = "scn_1";
  args.name = "bunny";
  args.crop = "-0.1,-0.1,0.001,0.1,0.1,0.2";
  args.initial = "Features";
  args.align_voxel = 0.002;
  args.max_distance = 0.01;
  args.min_fitness = 0.5;
  args.no_pose_graph = true;
  const auto spec = BuildModelSpec(ModelCommand::kAlign, args);
  ASSERT_TRUE(spec.ok()) << spec.status().message();

  v1::ModelSpec expected;
  expected.add_cloud_ids("cld_a");
  expected.add_cloud_ids("cld_b");
  expected.set_scene_id("scn_1");
  expected.set_name("bunny");
  *expected.mutable_crop()->mutable_min() = ToProto(Eigen::Vector3d(-0.1, -0.1, 0.001));
  *expected.mutable_crop()->mutable_max() = ToProto(Eigen::Vector3d(0.1, 0.1, 0.2));
  expected.mutable_alignment()->set_initial_pose(v1::INITIAL_POSE_FEATURES);
  expected.mutable_alignment()->set_voxel_size(0.002);
  expected.mutable_alignment()->set_max_correspondence_distance(0.01);
  expected.mutable_alignment()->set_min_fitness(0.5);
  expected.mutable_alignment()->set_skip_pose_graph(true);
  EXPECT_TRUE(MessageDifferencer::Equals(*spec, expected)) << spec->DebugString();
}

TEST(ModelArgs, AlignDefaultsLeaveChoicesToTheServer) {
  ModelArgs args;
  args.campaign_job_id = "job_1";
  const auto spec = BuildModelSpec(ModelCommand::kAlign, args);
  ASSERT_TRUE(spec.ok()) << spec.status().message();
  EXPECT_EQ(spec->campaign_job_id(), "job_1");
  EXPECT_EQ(spec->cloud_ids_size(), 0);
  EXPECT_EQ(spec->alignment().initial_pose(), v1::INITIAL_POSE_UNSPECIFIED);
  EXPECT_EQ(spec->alignment().voxel_size(), 0.0);
  EXPECT_FALSE(spec->skip_alignment());
  EXPECT_FALSE(spec->reconstruct());
  EXPECT_FALSE(spec->evaluate());
  EXPECT_FALSE(spec->has_crop());
  EXPECT_FALSE(spec->has_reconstruction());
  EXPECT_FALSE(spec->has_evaluation());
}

TEST(ModelArgs, ReconstructTakesVoxelForTheSurface) {
  ModelArgs args = TwoClouds();
  args.align_voxel = 0.003;
  args.method = "POISSON";
  args.reconstruction_voxel = 0.001;
  args.depth = 9;
  const auto spec = BuildModelSpec(ModelCommand::kReconstruct, args);
  ASSERT_TRUE(spec.ok()) << spec.status().message();
  EXPECT_TRUE(spec->reconstruct());
  EXPECT_FALSE(spec->evaluate());
  EXPECT_EQ(spec->alignment().voxel_size(), 0.003);
  EXPECT_EQ(spec->reconstruction().method(), v1::RECONSTRUCTION_METHOD_POISSON);
  EXPECT_EQ(spec->reconstruction().voxel_size(), 0.001);
  EXPECT_EQ(spec->reconstruction().poisson_depth(), 9u);
}

TEST(ModelArgs, EvaluateMapsItsOptions) {
  ModelArgs args = TwoClouds();
  args.tau = 0.0005;
  args.next_best_views = 5;
  args.mount_id = "mnt_1";
  auto spec = BuildModelSpec(ModelCommand::kEvaluate, args);
  ASSERT_TRUE(spec.ok()) << spec.status().message();
  EXPECT_TRUE(spec->evaluate());
  EXPECT_FALSE(spec->reconstruct());
  EXPECT_EQ(spec->evaluation().tau(), 0.0005);
  EXPECT_EQ(spec->evaluation().next_best_views(), 5u);
  EXPECT_FALSE(spec->evaluation().skip_next_best_views());
  EXPECT_EQ(spec->mount_id(), "mnt_1");

  args.next_best_views.reset();
  args.no_next_best_views = true;
  args.reconstruct = true;
  args.method = "tsdf";
  args.skip_alignment = true;
  spec = BuildModelSpec(ModelCommand::kEvaluate, args);
  ASSERT_TRUE(spec.ok()) << spec.status().message();
  EXPECT_TRUE(spec->evaluation().skip_next_best_views());
  EXPECT_TRUE(spec->reconstruct());
  EXPECT_TRUE(spec->skip_alignment());
  EXPECT_EQ(spec->reconstruction().method(), v1::RECONSTRUCTION_METHOD_TSDF);
}

TEST(ModelArgs, Rejections) {
  const auto rejects = [](ModelCommand command, ModelArgs args, const std::string& option) {
    ExpectInvalidNaming(BuildModelSpec(command, args).status(), option);
  };
  rejects(ModelCommand::kAlign, ModelArgs{}, "CLOUD_ID");  // no input
  ModelArgs both = TwoClouds();
  both.campaign_job_id = "job_1";
  rejects(ModelCommand::kAlign, both, "CLOUD_ID");

  const std::pair<std::function<void(ModelArgs&)>, std::string> cases[] = {
      {[](ModelArgs& a) { a.initial = "guess"; }, "--initial"},
      {[](ModelArgs& a) { a.align_voxel = -0.001; }, "--voxel"},
      {[](ModelArgs& a) { a.align_voxel = std::nan(""); }, "--voxel"},
      {[](ModelArgs& a) { a.max_distance = INFINITY; }, "--max-distance"},
      {[](ModelArgs& a) { a.min_fitness = 1.5; }, "--min-fitness"},
      {[](ModelArgs& a) { a.min_fitness = std::nan(""); }, "--min-fitness"},
      {[](ModelArgs& a) { a.crop = "0,0,0,1,1"; }, "--crop"},
      {[](ModelArgs& a) { a.crop = "0,0,1,1,1,0.5"; }, "--crop"},
  };
  for (const auto& [edit, option] : cases) {
    ModelArgs args = TwoClouds();
    edit(args);
    rejects(ModelCommand::kAlign, args, option);
  }
  // In reconstruct and evaluate --voxel is the surface's; the alignment's is --align-voxel.
  ModelArgs voxel = TwoClouds();
  voxel.align_voxel = -1;
  rejects(ModelCommand::kReconstruct, voxel, "--align-voxel");
  voxel = TwoClouds();
  voxel.reconstruction_voxel = -1;
  rejects(ModelCommand::kReconstruct, voxel, "--voxel");

  ModelArgs method = TwoClouds();
  method.method = "marching";
  rejects(ModelCommand::kReconstruct, method, "--method");
  // Reconstruction options without --reconstruct would be ignored: refused instead.
  method.method = "tsdf";
  rejects(ModelCommand::kEvaluate, method, "--method");
  ModelArgs depth = TwoClouds();
  depth.depth = 8;
  rejects(ModelCommand::kEvaluate, depth, "--depth");

  ModelArgs skip = TwoClouds();
  skip.skip_alignment = true;
  skip.initial = "known";
  rejects(ModelCommand::kReconstruct, skip, "--initial");
  skip.initial.clear();
  skip.no_pose_graph = true;
  rejects(ModelCommand::kReconstruct, skip, "--no-pose-graph");

  ModelArgs views = TwoClouds();
  views.next_best_views = 2;
  views.no_next_best_views = true;
  rejects(ModelCommand::kEvaluate, views, "--no-next-best-views");
  views = TwoClouds();
  views.tau = -0.001;
  rejects(ModelCommand::kEvaluate, views, "--tau");
}

TEST(ModelArgs, ServerErrorsNameTheOption) {
  const Status voxel = InvalidArgument("spec.alignment.voxel_size", "must be at most 0.1 m");
  EXPECT_EQ(NameOptionInError(ModelCommand::kAlign, voxel).message(),
            "--voxel: spec.alignment.voxel_size: must be at most 0.1 m");
  EXPECT_EQ(NameOptionInError(ModelCommand::kEvaluate, voxel).message(),
            "--align-voxel: spec.alignment.voxel_size: must be at most 0.1 m");
  EXPECT_EQ(NameOptionInError(ModelCommand::kEvaluate, voxel).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(NameOptionInError(ModelCommand::kReconstruct,
                              InvalidArgument("spec.reconstruction.voxel_size", "too small")).message(),
            "--voxel: spec.reconstruction.voxel_size: too small");
  EXPECT_EQ(NameOptionInError(ModelCommand::kAlign, NotFound("spec.cloud_ids[2]", "no cloud 'cld_x'")).message(),
            "CLOUD_ID[2]: spec.cloud_ids[2]: no cloud 'cld_x'");
  EXPECT_EQ(OptionForSpecField(ModelCommand::kAlign, "spec.crop.min.x: NaN"), "--crop");
  EXPECT_EQ(OptionForSpecField(ModelCommand::kEvaluate, "spec.evaluation.next_best_views: at most 20"),
            "--next-best-views");
  EXPECT_EQ(OptionForSpecField(ModelCommand::kEvaluate, "spec.reconstruction.method: needs pixels"), "--method");
  EXPECT_EQ(OptionForSpecField(ModelCommand::kEvaluate, "spec.mount_id: no mount 'm'"), "--mount");
  EXPECT_EQ(OptionForSpecField(ModelCommand::kEvaluate, "spec.scene_id_extra: x"), std::nullopt);
  EXPECT_EQ(OptionForSpecField(ModelCommand::kEvaluate, "the server is tired"), std::nullopt);
  // Trouble of the server itself is passed on as it is.
  const Status down = Unavailable("spec.scene_id: connection reset");
  EXPECT_EQ(NameOptionInError(ModelCommand::kAlign, down).message(), down.message());
}

}  // namespace
}  // namespace vscan::cli
