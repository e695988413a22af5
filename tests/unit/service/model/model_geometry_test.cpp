// The geometry a model job rests on, against answers worked out by hand: the model frame undoes the
// table's turn, crops cut meshes exactly, the default crop hugs the truth, a mesh PLY reads back,
// poses are fitted, covered samples are told from uncovered ones, and model.json parses.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "api/reports/proto_report_writer.h"
#include "evaluation/surface_sampling.h"
#include "geometry/mesh_import.h"
#include "model_test_block.h"
#include "model_test_json.h"
#include "scenes/scene_registry.h"
#include "service/model/model_alignment.h"
#include "service/model/model_crop.h"
#include "service/model/model_evaluation.h"
#include "service/model/model_frame.h"
#include "service/model/model_mesh_ply.h"
#include "service/model/model_report.h"
#include "vscan_test/meshes.h"

namespace vscan::service {
namespace {

constexpr double kBlockArea = 0.026;
constexpr double kBlockBottom = 0.08 * 0.06;
constexpr double kBasePerimeter = 2 * (0.08 + 0.06);

Pose3 RandomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return pose;
}

TEST(ModelFrameTest, TurningBackByTheTableAngleRestoresTheObjectAtZeroDegrees) {
  store::SceneRecord scene;
  scene.table.enabled = true;
  scene.table.centre = Eigen::Vector3d(0.1, -0.2, 0.05);
  scene.table.axis = Eigen::Vector3d(0.1, 0.0, 1.0);
  store::ObjectRecord object;
  object.on_table = true;
  object.pose.block<3, 1>(0, 3) = Eigen::Vector3d(0.12, -0.15, 0.08);
  const Eigen::Vector3d p(0.01, 0.02, 0.03);
  for (const double angle : {0.0, 30.0, -145.0, 720.5}) {
    const Eigen::Vector3d world = scenes::SceneRegistry::WorldFromObject(scene, object, angle) * p;
    const Eigen::Vector3d model = ModelFromWorld(scene.table, angle) * world;
    EXPECT_LT((model - scenes::SceneRegistry::WorldFromObject(scene, object, 0.0) * p).norm(), 1e-12) << angle;
    EXPECT_LT((WorldFromModel(scene.table, angle) * model - world).norm(), 1e-12) << angle;
  }
  // Without a table, or without an angle, the model frame is the world.
  EXPECT_TRUE(ModelFromWorld(std::nullopt, 30.0).isApprox(Pose3::Identity()));
  EXPECT_TRUE(ModelFromWorld(scene.table, std::nullopt).isApprox(Pose3::Identity()));
}

TEST(ModelCropTest, ABoxCutsAMeshExactlyAtItsFaces) {
  const TriangleMesh cube = test::MakeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  const ModelCrop crop = BoxCrop({Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(2, 2, 0.25)});
  const TriangleMesh cut = ClipMesh(cube, crop);
  // The bottom face and a quarter of each side.
  EXPECT_NEAR(evaluation::SurfaceArea(cut), 1.0 + 4 * 0.25, 1e-6);
  for (const Eigen::Vector3f& v : cut.vertices) EXPECT_TRUE(crop.Contains(v));
  EXPECT_TRUE(ClipMesh(cube, BoxCrop({Eigen::Vector3d(2, 2, 2), Eigen::Vector3d(3, 3, 3)})).empty());
  EXPECT_NEAR(evaluation::SurfaceArea(ClipMesh(cube, ModelCrop{})), 6.0, 1e-6);
}

TEST(ModelCropTest, TheDefaultCylinderCutsTheTableTopAndTheBaseAndKeepsTheRest) {
  const TriangleMesh block = testing::LBlock();
  const ModelCrop crop = CylinderAround(block, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 2));
  ASSERT_EQ(crop.kind, ModelCrop::Kind::kCylinder);
  const double diagonal = std::sqrt(0.08 * 0.08 + 0.06 * 0.06 + 0.07 * 0.07);
  EXPECT_NEAR(crop.base.z(), 0.001, 1e-9);
  EXPECT_NEAR(crop.radius, std::hypot(0.04, 0.03) + 0.02 * diagonal, 1e-6);
  EXPECT_NEAR(crop.base.z() + crop.height, 0.07 + 0.02 * diagonal, 1e-6);
  EXPECT_FALSE(crop.Contains(Eigen::Vector3f(0, 0, 0.0005f)));  // the table top
  EXPECT_TRUE(crop.Contains(Eigen::Vector3f(0.04f, 0.03f, 0.0015f)));
  EXPECT_FALSE(crop.Contains(Eigen::Vector3f(0.06f, 0.03f, 0.02f)));
  // What a scan of the block on its table can see: all but the base and a 1 mm strip above it.
  EXPECT_NEAR(evaluation::SurfaceArea(ClipMesh(block, crop)), kBlockArea - kBlockBottom - kBasePerimeter * 0.001,
              1e-7);
}

TEST(ModelMeshPlyTest, AMeshReadsBackFromItsPly) {
  const TriangleMesh block = testing::LBlock();
  const auto read = geometry::ImportMesh(EncodeMeshPly(block), geometry::MeshFileFormat::kPly, 1.0);
  ASSERT_TRUE(read.ok()) << read.status().ToString();
  EXPECT_EQ(read->triangles.size(), block.triangles.size());
  EXPECT_NEAR(evaluation::SurfaceArea(*read), kBlockArea, 1e-7);
  // A first coordinate of 0.0f starts the data with a byte that reads as a line end.
  const TriangleMesh cube = test::MakeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  ASSERT_EQ(cube.vertices.front().x(), 0.0f);
  const auto cube_read = geometry::ImportMesh(EncodeMeshPly(cube), geometry::MeshFileFormat::kPly, 1.0);
  ASSERT_TRUE(cube_read.ok()) << cube_read.status().ToString();
  EXPECT_NEAR(evaluation::SurfaceArea(*cube_read), 6.0, 1e-6);
}

TEST(FitPosesTest, FindsTheMotionBetweenTwoSetsOfPoses) {
  std::mt19937 rng(3);
  const Pose3 motion = RandomPose(rng);
  std::vector<Pose3> from, to;
  for (int i = 0; i < 5; ++i) {
    from.push_back(RandomPose(rng));
    to.push_back(motion * from.back());
  }
  const Pose3 fit = FitPoses(from, to, 0.3);
  EXPECT_LT(RotationErrorDeg(fit, motion), 1e-6);
  EXPECT_LT(TranslationError(fit, motion), 1e-9);
  EXPECT_NEAR(RotationErrorDeg(Pose3(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX())), Pose3::Identity()),
              0.1 * 180 / std::numbers::pi, 1e-9);
}

TEST(CoveredMaskTest, UncoveredSamplesAreFoundInOrderEvenWhenRepeated) {
  const std::vector<Eigen::Vector3f> samples = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  const std::vector<Eigen::Vector3f> uncovered = {{1, 0, 0}, {3, 0, 0}};
  EXPECT_EQ(CoveredMask(samples, uncovered), (std::vector<uint8_t>{1, 0, 1, 1, 0}));
}

TEST(ModelReportTest, ModelJsonHoldsTheSectionsThatRanWithTheirSummaries) {
  ModelReport report;
  report.job_id = "job_1";
  report.state = "SUCCEEDED";
  report.clouds = 2;
  report.crop = BoxCrop({Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)});
  ModelAlignmentReport& alignment = report.alignment.emplace();
  alignment.initial_pose = "known";
  for (int i = 0; i < 2; ++i) {
    ScanAlignmentRecord scan;
    scan.index = static_cast<uint32_t>(i);
    scan.name = "scan \"" + std::to_string(i) + "\"";
    scan.aligned = true;
    scan.has_error = true;
    scan.rotation_error_deg = 0.01 * (i + 1);
    scan.translation_error_m = 1e-4 * (i + 1);
    scan.initial_rotation_error_deg = 0.1;
    alignment.scans.push_back(scan);
  }
  const auto json = testing::JsonValue::Parse(api::ProtoReportWriter().ModelJson(report));
  EXPECT_EQ(json["kind"].text(), "model");
  EXPECT_EQ(json["crop"]["kind"].text(), "bounds");
  EXPECT_EQ(json["alignment"]["aligned"].number(), 2);
  EXPECT_NEAR(json["alignment"]["rotation_error_deg"]["mean"].number(), 0.015, 1e-12);
  EXPECT_NEAR(json["alignment"]["translation_error_m"]["max"].number(), 2e-4, 1e-12);
  EXPECT_EQ(json["alignment"]["scans"][1]["name"].text(), "scan \"1\"");
  EXPECT_EQ(json["alignment"]["scans"][1]["pose"].size(), 16u);
  EXPECT_FALSE(json.Has("reconstruction"));
  EXPECT_FALSE(json.Has("evaluation"));
}

}  // namespace
}  // namespace vscan::service
