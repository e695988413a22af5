// Stored clouds through the service layer: uploads in PLY and PCD kept as canonical PLY with every
// field, what the client says about them, refusals that store nothing, reading back, deleting.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "service/clouds/cloud_store.h"
#include "service_world.h"
#include "vscan/common/cloud_io.h"
#include "vscan_test/clouds.h"

namespace vscan::service {
namespace {

constexpr uint32_t kEveryField = kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal;

std::string Ply(const PointCloud& cloud) { return EncodePly(cloud).value(); }

class CloudStoreTest : public ::testing::Test {
 protected:
  std::string Pcd(const PointCloud& cloud) {
    const std::string path = (world_.data_dir() / "upload.pcd").string();
    EXPECT_TRUE(WritePcd(cloud, path).ok());
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
  }

  size_t BlobFiles() {
    size_t files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(world_.blobs().root())) {
      files += entry.is_regular_file();
    }
    return files;
  }

  size_t Clouds() { return world_.clouds().List("", 1000).value().size(); }

  // The upload is refused with code, naming field, and leaves nothing behind.
  void ExpectRefused(std::string_view bytes, const CloudUpload& upload, StatusCode code, const std::string& field) {
    const size_t clouds = Clouds();
    const size_t blobs = BlobFiles();
    const auto imported = ImportCloud(world_.context(), bytes, upload);
    ASSERT_FALSE(imported.ok());
    EXPECT_EQ(imported.status().code(), code) << imported.status().ToString();
    EXPECT_TRUE(imported.status().message().starts_with(field + ": ")) << imported.status().message();
    EXPECT_EQ(Clouds(), clouds);
    EXPECT_EQ(BlobFiles(), blobs);
  }

  testing::ServiceWorld world_;
};

TEST_F(CloudStoreTest, APlyKeepsEveryFieldAndIsStoredAsItsCanonicalPly) {
  const PointCloud cloud = test::MakeCloud(kEveryField, 9000);
  CloudUpload upload;
  upload.name = "every field";
  const store::CloudRecord record = ImportCloud(world_.context(), Ply(cloud), upload).value();
  EXPECT_TRUE(record.cloud_id.starts_with("cld_"));
  EXPECT_EQ(record.name, "every field");
  EXPECT_EQ(record.points, 9000u);
  EXPECT_EQ(record.fields, kEveryField);
  EXPECT_EQ(record.origin, store::CloudOrigin::kUploaded);
  EXPECT_EQ(record.frame, store::CloudFrame::kWorld);
  EXPECT_FALSE(record.world_from_sensor.has_value());
  EXPECT_FALSE(record.camera.has_value());

  const StoredCloud stored = LoadCloud(StoredCloudsOf(world_.context()), record.cloud_id).value();
  EXPECT_EQ(stored.ply, Ply(cloud));
  EXPECT_EQ(stored.record.size_bytes, stored.ply.size());
  EXPECT_EQ(stored.record.sha256, record.sha256);
  test::ExpectSameCloud(cloud, ParsePly(stored.ply, "stored", UINT64_MAX).value());
}

TEST_F(CloudStoreTest, APcdBecomesTheSamePlyWhetherItsFormatIsGivenOrTold) {
  const PointCloud cloud = test::MakeCloud(kEveryField, 500);
  CloudUpload told;
  const store::CloudRecord from_pcd = ImportCloud(world_.context(), Pcd(cloud), told).value();
  CloudUpload given;
  given.format = CloudFileFormat::kPcd;
  const store::CloudRecord again = ImportCloud(world_.context(), Pcd(cloud), given).value();
  const store::CloudRecord from_ply = ImportCloud(world_.context(), Ply(cloud), told).value();
  EXPECT_EQ(from_pcd.name, "cloud");
  EXPECT_EQ(from_pcd.fields, kEveryField);
  EXPECT_EQ(from_pcd.sha256, from_ply.sha256);
  EXPECT_EQ(again.sha256, from_ply.sha256);
  EXPECT_EQ(LoadCloud(StoredCloudsOf(world_.context()), from_pcd.cloud_id).value().ply, Ply(cloud));
}

TEST_F(CloudStoreTest, WhatTheClientSaysAboutTheCloudIsKept) {
  CloudUpload upload;
  upload.scene_id = world_.EmptyScene();
  upload.frame = store::CloudFrame::kSensor;
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(0.5, -0.25, 1.0);
  upload.world_from_sensor = pose;
  upload.camera = sensor::CameraFromFov(64, 48, 60.0, 0.1, 4.0);
  const store::CloudRecord record =
      ImportCloud(world_.context(), Ply(test::MakeCloud(kFieldPosition, 3)), upload).value();
  const store::CloudRecord got = world_.clouds().Get(record.cloud_id).value();
  EXPECT_EQ(got.scene_id, upload.scene_id);
  EXPECT_EQ(got.frame, store::CloudFrame::kSensor);
  ASSERT_TRUE(got.world_from_sensor.has_value());
  EXPECT_EQ(*got.world_from_sensor, pose.matrix());
  ASSERT_TRUE(got.camera.has_value());
  EXPECT_EQ(got.camera->width, 64u);
  EXPECT_EQ(got.camera->fx, upload.camera->fx);
  EXPECT_EQ(got.camera->near, 0.1);
}

TEST_F(CloudStoreTest, BadFilesAreRefusedNamingCloudDataAndStoreNothing) {
  const CloudUpload upload;
  const std::string ply = Ply(test::MakeCloud(kFieldsDefault, 10));
  ExpectRefused("", upload, StatusCode::kInvalidArgument, "cloud data");
  ExpectRefused(std::string_view(ply).substr(0, ply.size() - 7), upload, StatusCode::kInvalidArgument, "cloud data");
  // ASCII PLY is read now (Open3D, PCL and CloudCompare write it); big-endian PLY is still refused.
  ExpectRefused("ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n123456789012",
                upload, StatusCode::kInvalidArgument, "cloud data");
  // A lying count and a word where a number goes in ASCII.
  const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nend_header\n";
  ExpectRefused(ascii + "1 2 3\n", upload, StatusCode::kInvalidArgument, "cloud data");
  ExpectRefused(ascii + "1 2 3\n4 5 6\n7 eight 9\n", upload, StatusCode::kInvalidArgument, "cloud data");
  ExpectRefused(Ply(test::MakeCloud(kFieldsDefault, 0)), upload, StatusCode::kInvalidArgument, "cloud data");
  CloudUpload as_pcd;
  as_pcd.format = CloudFileFormat::kPcd;
  ExpectRefused(ply, as_pcd, StatusCode::kInvalidArgument, "cloud data");
  ExpectRefused("solid cube\nfacet normal 0 0 1\n", upload, StatusCode::kInvalidArgument, "format");
}

TEST_F(CloudStoreTest, AnOrganisedAsciiCloudKeepsItsPointsAndDropsItsHoles) {
  const std::string pcd = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
                          "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
                          "0.5 0 1 0.25\nnan nan nan nan\n-0.5 0 1.5 0.75\nnan nan nan 0\n";
  const store::CloudRecord record = ImportCloud(world_.context(), pcd, CloudUpload{}).value();
  EXPECT_EQ(record.points, 2u);
  const std::string ply = LoadCloud(StoredCloudsOf(world_.context()), record.cloud_id).value().ply;
  const PointCloud stored = ParsePly(ply, "stored", UINT64_MAX).value();
  ASSERT_EQ(stored.size(), 2u);
  EXPECT_EQ(stored.positions[1], Eigen::Vector3f(-0.5f, 0, 1.5f));
  EXPECT_EQ(stored.intensities, (std::vector<float>{0.25f, 0.75f}));
  // Only some coordinates NaN is no hole but a bad point; all holes is no points.
  const std::string head = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nPOINTS 2\nDATA ascii\n";
  ExpectRefused(head + "1 2 3\n1 nan 3\n", CloudUpload{}, StatusCode::kInvalidArgument, "cloud data");
  ExpectRefused(head + "nan nan nan\nnan nan nan\n", CloudUpload{}, StatusCode::kInvalidArgument, "cloud data");
}

TEST_F(CloudStoreTest, PositionsMustBeFiniteAndWithinTheWorld) {
  const CloudUpload upload;
  PointCloud cloud = test::MakeCloud(kFieldsDefault | kFieldCleanPosition, 20);
  cloud.positions[17].y() = std::numeric_limits<float>::quiet_NaN();
  ExpectRefused(Ply(cloud), upload, StatusCode::kInvalidArgument, "cloud data");
  const Status nan = ImportCloud(world_.context(), Ply(cloud), upload).status();
  EXPECT_EQ(nan.message(), "cloud data: points[17] (x, y, z): NaN or infinite value");

  cloud.positions[17].y() = 0;
  cloud.positions[3].z() = -std::numeric_limits<float>::infinity();
  EXPECT_NE(ImportCloud(world_.context(), Ply(cloud), upload).status().message().find("points[3]"), std::string::npos);
  cloud.positions[3].z() = 2e4f;
  const Status far = ImportCloud(world_.context(), Ply(cloud), upload).status();
  EXPECT_EQ(far.message(), "cloud data: points[3] (x, y, z): beyond 10 km (|x|, |y|, |z| <= 1e4 m)");
  cloud.positions[3].z() = 1e4f;
  cloud.clean_positions[5].x() = std::numeric_limits<float>::infinity();
  const Status clean = ImportCloud(world_.context(), Ply(cloud), upload).status();
  EXPECT_EQ(clean.message(), "cloud data: points[5] (clean_x, clean_y, clean_z): NaN or infinite value");
  cloud.clean_positions[5].x() = 0;
  EXPECT_TRUE(ImportCloud(world_.context(), Ply(cloud), upload).ok());
}

TEST_F(CloudStoreTest, BadDescriptionsAreRefusedNamingTheirField) {
  const std::string ply = Ply(test::MakeCloud(kFieldPosition, 3));
  CloudUpload unknown_scene;
  unknown_scene.scene_id = "scn_0000000000000000";
  ExpectRefused(ply, unknown_scene, StatusCode::kNotFound, "scene_id");
  CloudUpload bad_camera;
  bad_camera.camera = sensor::CameraFromFov(64, 48, 60.0, 0.1, 4.0);
  bad_camera.camera->fx = 0;
  ExpectRefused(ply, bad_camera, StatusCode::kInvalidArgument, "camera.fx");
  CloudUpload far_pose;
  far_pose.world_from_sensor = Pose3::Identity();
  far_pose.world_from_sensor->translation().x() = 1e5;
  ExpectRefused(ply, far_pose, StatusCode::kInvalidArgument, "world_from_sensor");
}

TEST(CloudStoreLimitTest, CloudsBeyondTheUploadLimitAreResourceExhausted) {
  ServerOptions options;
  options.limits.max_upload_bytes = 4096;
  testing::ServiceWorld world(options);
  const CloudUpload upload;
  // 100 points of 36 bytes fit in 4096 bytes as a file (header included) and as arrays.
  EXPECT_TRUE(ImportCloud(world.context(), Ply(test::MakeCloud(kFieldsDefault, 100)), upload).ok());
  const Status file = ImportCloud(world.context(), Ply(test::MakeCloud(kFieldsDefault, 200)), upload).status();
  EXPECT_EQ(file.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(file.message().find("--max-upload-mib"), std::string::npos) << file.message();
  // Three one-byte coordinates a point: a small file that would grow past the limit once read.
  std::string small = "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty uchar x\n"
                      "property uchar y\nproperty uchar z\nend_header\n";
  small.append(3000, '\1');
  const Status grown = ImportCloud(world.context(), small, upload).status();
  EXPECT_EQ(grown.code(), StatusCode::kResourceExhausted) << grown.ToString();
  EXPECT_EQ(grown.field(), "cloud data");
  EXPECT_NE(grown.message().find("--max-upload-mib"), std::string::npos) << grown.message();
  EXPECT_EQ(world.clouds().List("", 10).value().size(), 1u);
}

TEST_F(CloudStoreTest, DeletingACloudCollectsItsBlobOnceNothingNamesIt) {
  const std::string ply = Ply(test::MakeCloud(kFieldsDefault, 50));
  const CloudUpload upload;
  const store::CloudRecord a = ImportCloud(world_.context(), ply, upload).value();
  const store::CloudRecord b = ImportCloud(world_.context(), ply, upload).value();
  const size_t blobs = BlobFiles();
  const store::CollectedBlobs kept = DeleteCloud(world_.context(), a.cloud_id).value();
  EXPECT_EQ(kept.files, 0u);
  EXPECT_EQ(BlobFiles(), blobs);
  EXPECT_EQ(LoadCloud(StoredCloudsOf(world_.context()), a.cloud_id).status().code(), StatusCode::kNotFound);
  const store::CollectedBlobs freed = DeleteCloud(world_.context(), b.cloud_id).value();
  EXPECT_EQ(freed.files, 1u);
  EXPECT_EQ(freed.bytes, ply.size());
  EXPECT_EQ(BlobFiles(), blobs - 1);
  const Status again = DeleteCloud(world_.context(), b.cloud_id).status();
  EXPECT_EQ(again.code(), StatusCode::kNotFound);
  EXPECT_EQ(again.field(), "cloud_id");
}

TEST_F(CloudStoreTest, DetectionReadsTheFirstLine) {
  EXPECT_EQ(DetectCloudFormat("ply\nformat"), CloudFileFormat::kPly);
  EXPECT_EQ(DetectCloudFormat("ply\r\nformat"), CloudFileFormat::kPly);
  EXPECT_EQ(DetectCloudFormat("# .PCD v0.7\nVERSION"), CloudFileFormat::kPcd);
  EXPECT_EQ(DetectCloudFormat("VERSION .7\nFIELDS"), CloudFileFormat::kPcd);
  EXPECT_EQ(DetectCloudFormat("FIELDS x y z\n"), CloudFileFormat::kPcd);
  EXPECT_EQ(DetectCloudFormat("plywood\n"), std::nullopt);
  EXPECT_EQ(DetectCloudFormat(""), std::nullopt);
}

}  // namespace
}  // namespace vscan::service
