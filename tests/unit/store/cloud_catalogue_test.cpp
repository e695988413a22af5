// Clouds as stored resources: round trips with and without a sensor pose and camera, paging and the
// job filter, deletion refused for a campaign's scans (they go with their job), and blob
// collection that spares a blob a cloud still names.

#include <gtest/gtest.h>

#include "store/blob_gc.h"
#include "store/blob_store.h"
#include "store/cloud_catalogue.h"
#include "store/database.h"
#include "store/job_catalogue.h"
#include "vscan/common/point_cloud.h"
#include "vscan_test/temp_dir.h"

namespace vscan::store {
namespace {

class CloudCatalogueTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto database = Database::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(database.ok()) << database.status().ToString();
    database_ = *database;
    clouds_ = std::make_unique<CloudCatalogue>(database_);
    jobs_ = std::make_unique<JobCatalogue>(database_);
    ASSERT_TRUE(blobs_.Open().ok());
  }

  CloudRecord Uploaded(const std::string& bytes, const std::string& name = "scan") {
    CloudRecord cloud;
    cloud.name = name;
    cloud.sha256 = blobs_.Put(bytes).value();
    cloud.size_bytes = bytes.size();
    cloud.points = 3;
    cloud.fields = kFieldPosition | kFieldNormal;
    auto inserted = clouds_->Insert(cloud);
    EXPECT_TRUE(inserted.ok()) << inserted.status().ToString();
    return *inserted;
  }

  std::string EndedJob() {
    JobRecord job;
    job.kind = "campaign";
    const std::string id = jobs_->InsertJob(job).value().job_id;
    EXPECT_TRUE(jobs_->UpdateProgress(id, {JobState::kSucceeded, "done", 1, 1}).ok());
    return id;
  }

  test::TempDir dir_;
  std::shared_ptr<Database> database_;
  std::unique_ptr<CloudCatalogue> clouds_;
  std::unique_ptr<JobCatalogue> jobs_;
  BlobStore blobs_{dir_.path() / "blobs"};
};

TEST_F(CloudCatalogueTest, AnUploadedCloudRoundTripsWithoutPose) {
  const CloudRecord inserted = Uploaded("ply bytes");
  EXPECT_TRUE(inserted.cloud_id.starts_with("cld_"));
  const CloudRecord got = clouds_->Get(inserted.cloud_id).value();
  EXPECT_EQ(got.name, "scan");
  EXPECT_EQ(got.sha256, inserted.sha256);
  EXPECT_EQ(got.points, 3u);
  EXPECT_EQ(got.fields, kFieldPosition | kFieldNormal);
  EXPECT_EQ(got.origin, CloudOrigin::kUploaded);
  EXPECT_TRUE(got.job_id.empty());
  EXPECT_FALSE(got.world_from_sensor.has_value());
  EXPECT_FALSE(got.camera.has_value());
  EXPECT_FALSE(got.table_angle_deg.has_value());
  EXPECT_EQ(got.frame, CloudFrame::kWorld);
  EXPECT_GT(got.create_time_ms, 0);
}

TEST_F(CloudCatalogueTest, TheFrameOfThePointsIsKept) {
  CloudRecord cloud;
  cloud.sha256 = blobs_.Put("sensor frame").value();
  cloud.frame = CloudFrame::kSensor;
  cloud.world_from_sensor = Eigen::Matrix4d::Identity();
  EXPECT_EQ(clouds_->Get(clouds_->Insert(cloud).value().cloud_id).value().frame, CloudFrame::kSensor);
}

TEST_F(CloudCatalogueTest, AnArtifactRecordedAsAScanIsACloudOfItsJob) {
  JobRecord job;
  job.kind = "campaign";
  const std::string job_id = jobs_->InsertJob(job).value().job_id;
  ASSERT_TRUE(jobs_->UpdateProgress(job_id, {JobState::kRunning, "running", 0, 1}).ok());
  ArtifactRecord artifact;
  artifact.job_id = job_id;
  artifact.name = "scan-r00-v00.ply";
  artifact.media_type = "model/ply";
  artifact.sha256 = blobs_.Put("scan bytes").value();
  artifact.size_bytes = 10;
  CloudRecord scan;
  scan.name = artifact.name;
  scan.points = 2;
  scan.fields = kFieldPosition;
  scan.scene_id = "scn_0123456789abcdef";
  scan.table_angle_deg = 90.0;
  const ArtifactRecord stored =
      jobs_->AddArtifact(artifact, {JobState::kRunning, "scan 1", 1, 2}, &scan).value();
  EXPECT_TRUE(scan.cloud_id.starts_with("cld_"));
  const CloudRecord got = clouds_->Get(scan.cloud_id).value();
  EXPECT_EQ(got.origin, CloudOrigin::kCampaignScan);
  EXPECT_EQ(got.job_id, job_id);
  EXPECT_EQ(got.sha256, stored.sha256);
  EXPECT_EQ(got.size_bytes, 10u);
  EXPECT_EQ(got.table_angle_deg, 90.0);
  EXPECT_EQ(clouds_->List("", 10, job_id).value().size(), 1u);

  ASSERT_TRUE(jobs_->UpdateProgress(job_id, {JobState::kSucceeded, "done", 1, 3}).ok());
  const std::vector<std::string> named = jobs_->DeleteJob(job_id).value();
  EXPECT_EQ(named, std::vector<std::string>{stored.sha256});
  EXPECT_EQ(clouds_->Get(scan.cloud_id).status().code(), StatusCode::kNotFound);
}

TEST_F(CloudCatalogueTest, ACampaignScanKeepsItsPoseCameraAndAngle) {
  CloudRecord cloud;
  cloud.name = "scan-r00-v01.ply";
  cloud.sha256 = blobs_.Put("bytes").value();
  cloud.origin = CloudOrigin::kCampaignScan;
  cloud.job_id = EndedJob();
  cloud.scene_id = "scn_0123456789abcdef";
  cloud.fields = kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal;
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose(0, 3) = 0.25;
  pose(2, 1) = -1.0;
  cloud.world_from_sensor = pose;
  cloud.camera = CloudCamera{640, 480, 500.5, 501.0, 319.5, 239.5, 0.1, 2.5};
  cloud.table_angle_deg = -45.0;
  const CloudRecord got = clouds_->Get(clouds_->Insert(cloud).value().cloud_id).value();
  EXPECT_EQ(got.origin, CloudOrigin::kCampaignScan);
  EXPECT_EQ(got.job_id, cloud.job_id);
  EXPECT_EQ(got.scene_id, cloud.scene_id);
  EXPECT_EQ(got.fields, cloud.fields);
  ASSERT_TRUE(got.world_from_sensor.has_value());
  EXPECT_EQ(*got.world_from_sensor, pose);
  ASSERT_TRUE(got.camera.has_value());
  EXPECT_EQ(got.camera->width, 640u);
  EXPECT_EQ(got.camera->fy, 501.0);
  EXPECT_EQ(got.camera->far, 2.5);
  EXPECT_EQ(got.table_angle_deg, -45.0);
}

TEST_F(CloudCatalogueTest, ListPagesByIdAndFiltersByJob) {
  std::vector<std::string> ids;
  for (int i = 0; i < 5; ++i) ids.push_back(Uploaded("cloud " + std::to_string(i)).cloud_id);
  std::sort(ids.begin(), ids.end());
  const auto first = clouds_->List("", 2).value();
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[1].cloud_id, ids[1]);
  const auto rest = clouds_->List(first.back().cloud_id, 10).value();
  ASSERT_EQ(rest.size(), 3u);
  EXPECT_EQ(rest[0].cloud_id, ids[2]);

  CloudRecord scan;
  scan.sha256 = blobs_.Put("scan").value();
  scan.origin = CloudOrigin::kCampaignScan;
  scan.job_id = EndedJob();
  const std::string scan_id = clouds_->Insert(scan).value().cloud_id;
  const auto of_job = clouds_->List("", 10, scan.job_id).value();
  ASSERT_EQ(of_job.size(), 1u);
  EXPECT_EQ(of_job[0].cloud_id, scan_id);
  EXPECT_EQ(clouds_->List("", 0).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(CloudCatalogueTest, DeletingAnUploadFreesItsBlobUnlessAnotherCloudNamesIt) {
  const CloudRecord a = Uploaded("same bytes", "a");
  const CloudRecord b = Uploaded("same bytes", "b");
  ASSERT_EQ(a.sha256, b.sha256);
  const std::string sha = clouds_->Delete(a.cloud_id).value();
  EXPECT_EQ(CollectBlobs(*database_, blobs_, {sha}).value().files, 0u);  // b still names it
  EXPECT_TRUE(blobs_.Get(sha).ok());
  EXPECT_EQ(clouds_->Get(a.cloud_id).status().code(), StatusCode::kNotFound);
  ASSERT_TRUE(clouds_->Delete(b.cloud_id).ok());
  EXPECT_EQ(CollectBlobs(*database_, blobs_, {sha}).value().files, 1u);
  EXPECT_FALSE(blobs_.Get(sha).ok());
  EXPECT_EQ(clouds_->Delete(b.cloud_id).status().code(), StatusCode::kNotFound);
}

TEST_F(CloudCatalogueTest, ACampaignScanGoesWithItsJobNotAlone) {
  CloudRecord scan;
  scan.sha256 = blobs_.Put("scan").value();
  scan.origin = CloudOrigin::kCampaignScan;
  scan.job_id = EndedJob();
  const std::string id = clouds_->Insert(scan).value().cloud_id;
  const Status refused = clouds_->Delete(id).status();
  EXPECT_EQ(refused.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(refused.field(), "cloud_id");
  ASSERT_TRUE(jobs_->DeleteJob(scan.job_id).ok());
  EXPECT_EQ(clouds_->Get(id).status().code(), StatusCode::kNotFound);

  CloudRecord orphan = scan;
  orphan.job_id.clear();
  EXPECT_EQ(clouds_->Insert(orphan).status().code(), StatusCode::kInvalidArgument);
}

TEST(CloudFieldNamesTest, NamesRoundTripAndUnknownNamesAreDataLoss) {
  const uint32_t every = kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal;
  EXPECT_EQ(FieldsFromNames(FieldNames(every), "here").value(), every);
  EXPECT_EQ(FieldNames(kFieldPosition | kFieldRange), "position,range");
  EXPECT_EQ(FieldsFromNames("", "here").value(), 0u);
  EXPECT_EQ(FieldsFromNames("position,colour", "here").status().code(), StatusCode::kDataLoss);
}

}  // namespace
}  // namespace vscan::store
