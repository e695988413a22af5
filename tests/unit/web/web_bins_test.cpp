// /api/bins over a real job catalogue and blob store: a fill's parts and bin from its bin.json, its
// replay's bytes as stored, and the 404s for fills without a replay and for other jobs.

#include <gtest/gtest.h>

#include "api/job/job_tracker.h"
#include "store/blob_store.h"
#include "vscan/common/report_json.h"
#include "vscan/v1/job.pb.h"
#include "vscan/v1/reports.pb.h"
#include "vscan_test/temp_dir.h"
#include "web/web_api.h"

namespace vscan::web {
namespace {

class WebBinsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto opened = store::JobCatalogue::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(opened.ok()) << opened.status().ToString();
    catalogue_ = std::move(opened).value();
    ASSERT_TRUE(blobs_.Open().ok());
    tracker_ = std::make_unique<api::JobTracker>(*catalogue_, blobs_);
  }

  WebApi Api() { return WebApi(WebSources{.jobs = tracker_.get()}, WebApiOptions{.token = "s3cret"}); }
  WebReply Get(const std::string& path) { return Api().Handle("GET", path, "", "Bearer s3cret"); }

  std::string Create(service::JobKind kind, const std::string& name) {
    auto job = tracker_->Create(kind, name, v1::BinFillSpec(), 2);
    EXPECT_TRUE(job.ok()) << job.status().ToString();
    return job.ok() ? job->job_id() : "";
  }

  void Store(const std::string& job_id, const std::string& name, const std::string& bytes) {
    service::JobEventUpdate update;
    update.message = name + " written";
    ASSERT_TRUE(tracker_->RecordArtifact(job_id, name, "application/octet-stream", bytes, nullptr, update).ok());
  }

  void End(const std::string& job_id) {
    service::JobEventUpdate update;
    update.state = store::JobState::kSucceeded;
    update.message = "settled: 2 parts in the bin";
    update.steps_done = 2;
    ASSERT_TRUE(tracker_->End(job_id, update).ok());
  }

  // A settled box bin of two parts, as vscand prints bin.json.
  static std::string BinJson(const std::string& job_id) {
    v1::BinReport report;
    report.set_job_id(job_id);
    report.set_name("pile");
    report.set_scene_id("scn_1");
    report.set_applied(true);
    report.set_scene_revision(4);
    report.set_end("settled");
    report.set_simulated_s(2.5);
    v1::BinReportBin* bin = report.mutable_bin();
    for (double v : {0.3, 0.2, 0.1}) bin->mutable_inner_size()->add_values()->set_number_value(v);
    bin->set_wall_thickness(0.01);
    for (int i = 0; i < 16; ++i) bin->add_world_from_bin(i % 5 == 0 ? 1 : 0);
    bin->set_mesh_id("msh_bin");
    bin->set_object_id("obj_bin");
    bin->set_instance_id(1);
    v1::BinReportType* type = report.add_types();
    type->set_name("block");
    type->set_mesh_id("msh_block");
    type->set_scale(0.5);
    type->set_count(2);
    for (uint32_t k = 0; k < 2; ++k) {
      v1::BinReportPart* part = report.add_parts();
      part->set_name("block");
      part->set_instance(k);
      part->set_mesh_id("msh_block");
      part->set_scale(0.5);
      part->set_object_id("obj_" + std::to_string(k));
      part->set_instance_id(2 + k);
      part->set_label("block#" + std::to_string(k + 1));
      for (int i = 0; i < 16; ++i) part->add_world_from_part(i % 5 == 0 ? 1 : (i == 11 ? 0.05 * (k + 1) : 0));
    }
    return PrintReport(report);
  }

  test::TempDir dir_;
  std::unique_ptr<store::JobCatalogue> catalogue_;
  store::BlobStore blobs_{dir_.path() / "blobs"};
  std::unique_ptr<api::JobTracker> tracker_;
};

TEST_F(WebBinsTest, AFillShowsItsPartsAndServesItsReplay) {
  const std::string id = Create(service::JobKind::kBinFill, "pile");
  const std::string replay("VSBR\x01\0\0\0 replay bytes \xff", 23);
  Store(id, "bin_replay.bin", replay);
  Store(id, "bin.json", BinJson(id));
  End(id);

  const WebReply reply = Get("/api/bins/" + id);
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.content_type, "application/json");
  for (const std::string& expected :
       {"\"job_id\":\"" + id + "\"", std::string("\"state\":\"SUCCEEDED\""), std::string("\"replay\":true"),
        std::string("\"scene_id\":\"scn_1\""), std::string("\"scene_revision\":4"),
        std::string("\"bin\":{\"kind\":\"box\",\"inner_size\":[0.3,0.2,0.1],\"wall_thickness\":0.01"),
        std::string("\"types\":[{\"type\":0,\"name\":\"block\",\"mesh_id\":\"msh_block\",\"scale\":0.5"),
        std::string("{\"type\":0,\"name\":\"block\",\"instance\":1,\"label\":\"block#2\",\"mesh_id\":\"msh_block\","
                    "\"scale\":0.5,\"object_id\":\"obj_1\",\"instance_id\":3,"
                    "\"world_from_part\":[[1,0,0,0],[0,1,0,0],[0,0,1,0.1],[0,0,0,1]]}")}) {
    EXPECT_NE(reply.body.find(expected), std::string::npos) << expected << "\n" << reply.body;
  }

  const WebReply bytes = Get("/api/bins/" + id + "/replay");
  ASSERT_EQ(bytes.status, 200);
  EXPECT_EQ(bytes.content_type, "application/octet-stream");
  EXPECT_EQ(bytes.body, replay);
  EXPECT_EQ(Api().Handle("GET", "/api/bins/" + id + "/replay", "", "Bearer wrong").status, 401);
}

TEST_F(WebBinsTest, AFillWithoutAReplayOrReportSaysSo) {
  const std::string running = Create(service::JobKind::kBinFill, "running");
  WebReply reply = Get("/api/bins/" + running);
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_NE(reply.body.find("\"state\":\"QUEUED\""), std::string::npos) << reply.body;
  EXPECT_NE(reply.body.find("\"report\":false"), std::string::npos) << reply.body;
  EXPECT_NE(reply.body.find("\"parts\":[]"), std::string::npos) << reply.body;

  // A fill from before the replay: bin.json alone.
  const std::string older = Create(service::JobKind::kBinFill, "older");
  Store(older, "bin.json", BinJson(older));
  End(older);
  reply = Get("/api/bins/" + older);
  ASSERT_EQ(reply.status, 200);
  EXPECT_NE(reply.body.find("\"replay\":false"), std::string::npos) << reply.body;
  EXPECT_NE(reply.body.find("\"object_id\":\"obj_0\""), std::string::npos) << reply.body;
  reply = Get("/api/bins/" + older + "/replay");
  EXPECT_EQ(reply.status, 404);
  EXPECT_NE(reply.body.find(older), std::string::npos) << reply.body;
}

TEST_F(WebBinsTest, OtherJobsAndUnknownIdsAreRefused) {
  const std::string campaign = Create(service::JobKind::kCampaign, "campaign");
  for (const std::string& path : {"/api/bins/" + campaign, "/api/bins/" + campaign + "/replay"}) {
    const WebReply reply = Get(path);
    EXPECT_EQ(reply.status, 404) << path;
    EXPECT_NE(reply.body.find(campaign), std::string::npos) << reply.body;
    EXPECT_NE(reply.body.find("campaign job, not a bin fill"), std::string::npos) << reply.body;
  }
  const std::string fill = Create(service::JobKind::kBinFill, "fill");
  for (const std::string& path : {std::string("/api/bins/job_0000000000000000"), std::string("/api/bins"),
                                  std::string("/api/bins/"), "/api/bins/" + fill + "/other",
                                  "/api/bins/" + fill + "/replay/more", std::string("/api/bins/a.b")}) {
    EXPECT_EQ(Get(path).status, 404) << path;
  }
  // A view without the job tracker serves no bins.
  const WebApi scenes_only(WebSources{}, WebApiOptions{});
  EXPECT_EQ(scenes_only.Handle("GET", "/api/bins/" + fill, "", "").status, 404);
}

}  // namespace
}  // namespace vscan::web
