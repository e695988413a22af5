// The web view's jobs and clouds: how clouds are thinned and laid out for the page, what the API
// refuses, and that event streams end with the job, with the client and with the view.

#include <chrono>
#include <cstring>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "api/job/job_tracker.h"
#include "store/blob_store.h"
#include "store/cloud_catalogue.h"
#include "store/job_catalogue.h"
#include "vscan/common/cloud_io.h"
#include "vscan_test/temp_dir.h"
#include "web/web_api.h"
#include "web/web_clouds.h"
#include "web/web_jobs.h"

namespace vscan::web {
namespace {

using namespace std::chrono_literals;

template <typename T>
T At(const std::string& bytes, size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

TEST(ThinnedIndicesTest, KeepsEveryPointThatFits) {
  EXPECT_EQ(ThinnedIndices(5, 5), (std::vector<uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(ThinnedIndices(3, 1000), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_TRUE(ThinnedIndices(0, 10).empty());
}

TEST(ThinnedIndicesTest, KeepsAtMostTheBoundEvenlySpacedAndTheSameEachTime) {
  for (const auto& [total, bound] : std::vector<std::pair<uint64_t, uint64_t>>{
           {10, 4}, {1000, 7}, {1'000'003, 1000}, {4'000'000'000ull, 5'000'000}, {12, 1}}) {
    const std::vector<uint32_t> keep = ThinnedIndices(total, bound);
    ASSERT_EQ(keep.size(), bound) << total;
    EXPECT_EQ(keep.front(), 0u);
    EXPECT_LT(keep.back(), total);
    // Strictly increasing with gaps of floor(total / bound) or one more: uniform over the cloud.
    const uint64_t gap = total / bound;
    for (size_t k = 1; k < keep.size(); ++k) {
      const uint64_t step = keep[k] - keep[k - 1];
      ASSERT_TRUE(step == gap || step == gap + 1) << total << " " << bound << " at " << k << ": " << step;
    }
    EXPECT_EQ(ThinnedIndices(total, bound), keep);
  }
}

PointCloud EveryField(size_t n) {
  PointCloud cloud;
  cloud.fields = kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal;
  cloud.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float f = static_cast<float>(i);
    cloud.positions[i] = {f, f + 0.5f, -f};
    cloud.normals[i] = {0, 0, 1};
    cloud.ranges[i] = 1 + f;
    cloud.intensities[i] = 0.01f * f;
    cloud.instance_ids[i] = static_cast<uint32_t>(100 + i);
    cloud.pixels[i] = static_cast<uint32_t>(7 * i);
    cloud.clean_positions[i] = {f, f, f};
    cloud.incidence_angles[i] = 0.1f;
    cloud.statuses[i] = static_cast<uint8_t>(i % 3);
    cloud.estimated_normals[i] = {1, 0, 0};
  }
  return cloud;
}

TEST(CloudBinaryTest, HeaderThenPositionsThenEachFieldOfTheKeptPoints) {
  const PointCloud cloud = EveryField(10);
  const std::string bytes = CloudBinary(cloud, 3, 640, 480);
  ASSERT_GE(bytes.size(), kCloudHeaderBytes);
  EXPECT_EQ(bytes.substr(0, 4), "VSCL");
  EXPECT_EQ(At<uint32_t>(bytes, 4), kCloudLayoutVersion);
  EXPECT_EQ(At<uint32_t>(bytes, 8), cloud.fields);
  EXPECT_EQ(At<uint32_t>(bytes, 12), 3u);
  EXPECT_EQ(At<uint64_t>(bytes, 16), 10u);
  EXPECT_EQ(At<uint32_t>(bytes, 24), 640u);
  EXPECT_EQ(At<uint32_t>(bytes, 28), 480u);
  const std::vector<uint32_t> kept = ThinnedIndices(10, 3);  // 0, 3, 6
  ASSERT_EQ(kept, (std::vector<uint32_t>{0, 3, 6}));
  size_t at = kCloudHeaderBytes;
  for (const uint32_t i : kept) {
    EXPECT_EQ(At<float>(bytes, at + 0), cloud.positions[i].x());
    EXPECT_EQ(At<float>(bytes, at + 4), cloud.positions[i].y());
    EXPECT_EQ(At<float>(bytes, at + 8), cloud.positions[i].z());
    at += 12;
  }
  at += 3 * 12;  // normals
  for (size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(At<float>(bytes, at + 4 * k), cloud.ranges[kept[k]]);
  at += 3 * 4;
  for (size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(At<float>(bytes, at + 4 * k), cloud.intensities[kept[k]]);
  at += 3 * 4;
  for (size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(At<uint32_t>(bytes, at + 4 * k), 100 + kept[k]);
  at += 3 * 4;
  for (size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(At<uint32_t>(bytes, at + 4 * k), 7 * kept[k]);
  at += 3 * 4;
  at += 3 * 12 + 3 * 4;  // clean positions, incidence
  for (size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(At<uint8_t>(bytes, at + k), kept[k] % 3);
  EXPECT_EQ(At<uint8_t>(bytes, at + 3), 0u);  // padded to 4 bytes
  at += 4;
  for (size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(At<float>(bytes, at + 12 * k), cloud.estimated_normals[kept[k]].x());
  at += 3 * 12;
  EXPECT_EQ(bytes.size(), at);
}

TEST(CloudBinaryTest, PositionsOnlyAndUnthinned) {
  PointCloud cloud;
  cloud.positions = {{1, 2, 3}, {4, 5, 6}};
  const std::string bytes = CloudBinary(cloud, 1'000'000, 0, 0);
  EXPECT_EQ(At<uint32_t>(bytes, 8), static_cast<uint32_t>(kFieldPosition));
  EXPECT_EQ(At<uint32_t>(bytes, 12), 2u);
  EXPECT_EQ(At<uint64_t>(bytes, 16), 2u);
  ASSERT_EQ(bytes.size(), kCloudHeaderBytes + 24);
  EXPECT_EQ(At<float>(bytes, kCloudHeaderBytes + 20), 6.0f);
}

class WebJobsCloudsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto database = store::Database::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(database.ok()) << database.status().ToString();
    jobs_ = std::make_unique<store::JobCatalogue>(*database);
    clouds_ = std::make_unique<store::CloudCatalogue>(*database);
    ASSERT_TRUE(blobs_.Open().ok());
    tracker_ = std::make_unique<api::JobTracker>(*jobs_, blobs_);
    const PointCloud cloud = EveryField(25);
    auto ply = EncodePly(cloud);
    ASSERT_TRUE(ply.ok());
    auto sha = blobs_.Put(*ply);
    ASSERT_TRUE(sha.ok());
    store::CloudRecord record;
    record.name = "every field";
    record.sha256 = *sha;
    record.size_bytes = ply->size();
    record.points = cloud.size();
    record.fields = cloud.fields;
    auto inserted = clouds_->Insert(record);
    ASSERT_TRUE(inserted.ok()) << inserted.status().ToString();
    cloud_id_ = inserted->cloud_id;
  }

  WebApi Api() {
    return WebApi(WebSources{.jobs = tracker_.get(), .clouds = clouds_.get(), .blobs = &blobs_},
                  WebApiOptions{.token = "t"});
  }
  WebReply Get(const WebApi& api, std::string_view path, std::string_view query = "") {
    return api.Handle("GET", path, query, "Bearer t");
  }

  std::string StartJob() {
    v1::CampaignSpec spec;
    spec.set_name("followed");
    auto job = tracker_->Create(service::JobKind::kCampaign, spec.name(), spec, 3);
    EXPECT_TRUE(job.ok());
    return job.ok() ? job->job_id() : "";
  }

  static service::JobEventUpdate Update(store::JobState state, uint32_t step) {
    service::JobEventUpdate update;
    update.state = state;
    update.message = "step " + std::to_string(step);
    update.steps_done = step;
    return update;
  }

  test::TempDir dir_;
  store::BlobStore blobs_{dir_.path() / "blobs"};
  std::unique_ptr<store::JobCatalogue> jobs_;
  std::unique_ptr<store::CloudCatalogue> clouds_;
  std::unique_ptr<api::JobTracker> tracker_;
  std::string cloud_id_;
};

TEST_F(WebJobsCloudsTest, CloudsComeThinnedToTheBoundAskedFor) {
  const WebApi api = Api();
  const std::string path = "/api/clouds/" + cloud_id_;
  WebReply reply = Get(api, path);
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.content_type, kBinaryType);
  EXPECT_EQ(At<uint32_t>(reply.body, 12), 25u);
  reply = Get(api, path, "max_points=10");
  ASSERT_EQ(reply.status, 200);
  EXPECT_EQ(At<uint32_t>(reply.body, 12), 10u);
  EXPECT_EQ(At<uint64_t>(reply.body, 16), 25u);
  // The instance ids of the points kept: evenly spaced over the stored order.
  const size_t instances = kCloudHeaderBytes + 10 * (12 + 12 + 4 + 4);
  for (uint32_t k = 0; k < 10; ++k) EXPECT_EQ(At<uint32_t>(reply.body, instances + 4 * k), 100 + k * 25 / 10);
  for (const char* bad : {"max_points=0", "max_points=5000001", "max_points=ten", "max_points=", "max_points=-3"}) {
    reply = Get(api, path, bad);
    EXPECT_EQ(reply.status, 400) << bad;
    EXPECT_NE(reply.body.find("max_points"), std::string::npos) << reply.body;
  }
  EXPECT_EQ(Get(api, "/api/clouds/cld_0000000000000000").status, 404);
  EXPECT_EQ(Get(api, "/api/clouds/" + cloud_id_ + "/nothing").status, 404);
  reply = Get(api, "/api/clouds/" + cloud_id_ + "/record");
  ASSERT_EQ(reply.status, 200);
  EXPECT_NE(reply.body.find("\"points\":25"), std::string::npos) << reply.body;
  EXPECT_NE(reply.body.find("\"instance_id\""), std::string::npos) << reply.body;
  EXPECT_EQ(api.Handle("GET", path, "", "Bearer x").status, 401);
}

TEST_F(WebJobsCloudsTest, CloudListsByJob) {
  const WebApi api = Api();
  WebReply reply = Get(api, "/api/clouds");
  ASSERT_EQ(reply.status, 200);
  EXPECT_NE(reply.body.find(cloud_id_), std::string::npos);
  EXPECT_EQ(Get(api, "/api/clouds", "job=a%2Fb").status, 400);
  EXPECT_EQ(Get(api, "/api/clouds", "job=job_0000000000000000").status, 404);
  const std::string job = StartJob();
  reply = Get(api, "/api/clouds", "job=" + job);
  ASSERT_EQ(reply.status, 200);
  EXPECT_EQ(reply.body, "{\"clouds\":[]}");
}

TEST_F(WebJobsCloudsTest, JobsListNewestFirstAndOneJobAsJson) {
  const WebApi api = Api();
  const std::string first = StartJob();
  std::this_thread::sleep_for(5ms);
  const std::string second = StartJob();
  WebReply reply = Get(api, "/api/jobs");
  ASSERT_EQ(reply.status, 200);
  ASSERT_NE(reply.body.find(first), std::string::npos);
  EXPECT_LT(reply.body.find(second), reply.body.find(first)) << reply.body;
  EXPECT_NE(reply.body.find("\"state\":\"QUEUED\""), std::string::npos) << reply.body;
  reply = Get(api, "/api/jobs", "limit=1");
  EXPECT_EQ(reply.body.find(first), std::string::npos);
  EXPECT_EQ(Get(api, "/api/jobs", "limit=0").status, 400);
  reply = Get(api, "/api/jobs/" + first);
  ASSERT_EQ(reply.status, 200);
  EXPECT_NE(reply.body.find("\"job_id\":\"" + first + "\""), std::string::npos) << reply.body;
  EXPECT_EQ(Get(api, "/api/jobs/job_0000000000000000").status, 404);
  EXPECT_EQ(Get(api, "/api/jobs/" + first + "/artifacts/art_0000000000000000").status, 404);
  EXPECT_EQ(Get(api, "/api/jobs/" + first + "/whatever").status, 404);
}

TEST_F(WebJobsCloudsTest, ArtifactsComeAsTheirBytesOrAsACloud) {
  const WebApi api = Api();
  const std::string job = StartJob();
  auto ply = EncodePly(EveryField(4));
  ASSERT_TRUE(ply.ok());
  auto scan = tracker_->RecordArtifact(job, "aligned.ply", "model/ply", *ply, nullptr, Update(store::JobState::kRunning, 1));
  ASSERT_TRUE(scan.ok()) << scan.status().ToString();
  auto report = tracker_->RecordArtifact(job, "model.json", "application/json", "{\"a\":1}", nullptr,
                                         Update(store::JobState::kRunning, 2));
  ASSERT_TRUE(report.ok());
  const std::string base = "/api/jobs/" + job + "/artifacts/";
  // The bytes are streamed a chunk at a time, with their length.
  auto read = [&](const std::string& artifact_id, std::string* content_type) {
    const WebReply reply = Get(api, base + artifact_id);
    EXPECT_EQ(reply.status, 200);
    *content_type = reply.content_type;
    std::string body;
    if (!reply.stream) return body;
    reply.stream([&](std::string_view bytes) {
      body.append(bytes);
      return true;
    });
    EXPECT_EQ(reply.stream_length, static_cast<long long>(body.size()));
    return body;
  };
  std::string type;
  EXPECT_EQ(read(report->artifact_id(), &type), "{\"a\":1}");
  EXPECT_EQ(type, "application/json");
  EXPECT_EQ(read(scan->artifact_id(), &type), *ply);
  EXPECT_EQ(type, "model/ply");
  WebReply reply = Get(api, base + scan->artifact_id(), "as=cloud&max_points=2");
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.body.substr(0, 4), "VSCL");
  EXPECT_EQ(At<uint32_t>(reply.body, 12), 2u);
  EXPECT_EQ(Get(api, base + report->artifact_id(), "as=cloud").status, 400);
  EXPECT_EQ(Get(api, base + scan->artifact_id(), "as=mesh").status, 400);
}

// Runs a stream as the web view would, collecting what it writes; write_ok says whether the client
// still reads.
struct Collected {
  std::mutex mutex;
  std::string text;
  std::atomic<bool> write_ok{true};
  bool Has(std::string_view part) {
    std::lock_guard lock(mutex);
    return text.find(part) != std::string::npos;
  }
};

std::future<void> RunStream(const WebReply& reply, Collected& out) {
  return std::async(std::launch::async, [stream = reply.stream, &out] {
    stream([&out](std::string_view bytes) {
      if (!out.write_ok) return false;
      std::lock_guard lock(out.mutex);
      out.text.append(bytes);
      return true;
    });
  });
}

bool WaitFor(const std::function<bool()>& done) {
  for (int i = 0; i < 500 && !done(); ++i) std::this_thread::sleep_for(10ms);
  return done();
}

TEST_F(WebJobsCloudsTest, AStreamSendsTheSnapshotThenEachEventAndEndsWithTheJob) {
  WebApi api = Api();
  const std::string job = StartJob();
  const WebReply reply = Get(api, "/api/jobs/" + job + "/events");
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.content_type, "text/event-stream");
  ASSERT_TRUE(reply.stream);
  Collected out;
  std::future<void> done = RunStream(reply, out);
  ASSERT_TRUE(WaitFor([&] { return out.Has("\"followed\""); }));
  ASSERT_TRUE(tracker_->Record(job, Update(store::JobState::kRunning, 1)).ok());
  ASSERT_TRUE(WaitFor([&] { return out.Has("step 1"); }));
  ASSERT_TRUE(tracker_->End(job, Update(store::JobState::kSucceeded, 3)).ok());
  ASSERT_EQ(done.wait_for(5s), std::future_status::ready);
  EXPECT_TRUE(out.Has("JOB_STATE_SUCCEEDED"));
  EXPECT_TRUE(out.text.ends_with("event: end\ndata: {}\n\n")) << out.text;
  // An ended job: the snapshot and the end.
  Collected again;
  RunStream(Get(api, "/api/jobs/" + job + "/events"), again).get();
  EXPECT_EQ(again.text.rfind("data: {\"job\":", 0), 0u) << again.text;
  EXPECT_TRUE(again.Has("event: end"));
  EXPECT_EQ(Get(api, "/api/jobs/job_0000000000000000/events").status, 404);
}

TEST_F(WebJobsCloudsTest, StreamsAreBoundedAndEndWhenTheClientGoesOrTheViewStops) {
  WebApi api = Api();
  const std::string job = StartJob();
  std::vector<WebReply> replies;
  for (int i = 0; i < 8; ++i) {
    replies.push_back(Get(api, "/api/jobs/" + job + "/events"));
    ASSERT_EQ(replies.back().status, 200);
  }
  EXPECT_EQ(Get(api, "/api/jobs/" + job + "/events").status, 503);
  // A reply dropped unsent gives its place back.
  replies.pop_back();
  ASSERT_EQ(Get(api, "/api/jobs/" + job + "/events").status, 200);  // and drops it again at once

  Collected gone;
  std::future<void> first = RunStream(replies[0], gone);
  ASSERT_TRUE(WaitFor([&] { return gone.Has("data:"); }));
  gone.write_ok = false;  // the client went: the next event's write fails and the stream ends
  ASSERT_TRUE(tracker_->Record(job, Update(store::JobState::kRunning, 1)).ok());
  EXPECT_EQ(first.wait_for(5s), std::future_status::ready);

  std::vector<Collected> outs(3);
  std::vector<std::future<void>> running;
  for (int i = 0; i < 3; ++i) running.push_back(RunStream(replies[1 + i], outs[i]));
  for (auto& out : outs) ASSERT_TRUE(WaitFor([&] { return out.Has("data:"); }));
  const auto stop = std::chrono::steady_clock::now();
  api.StopStreams();
  for (auto& r : running) EXPECT_EQ(r.wait_for(5s), std::future_status::ready);
  EXPECT_LT(std::chrono::steady_clock::now() - stop, 2s);
  // The job still runs; the streams did not wait for it, and no new one starts.
  EXPECT_NE(tracker_->Live(job), nullptr);
  EXPECT_EQ(Get(api, "/api/jobs/" + job + "/events").status, 503);
  replies.clear();
}

TEST(JobStreamsTest, WritesAKeepAliveCommentWhenNothingHappens) {
  test::TempDir dir;
  auto catalogue = store::JobCatalogue::Open(dir.path() / "catalogue.sqlite");
  ASSERT_TRUE(catalogue.ok());
  store::BlobStore blobs(dir.path() / "blobs");
  ASSERT_TRUE(blobs.Open().ok());
  api::JobTracker tracker(**catalogue, blobs);
  v1::CampaignSpec spec;
  auto job = tracker.Create(service::JobKind::kCampaign, "quiet", spec, 1);
  ASSERT_TRUE(job.ok());
  auto streams = std::make_shared<JobStreams>(2, 50ms);
  const WebReply reply = ServeJobs(WebSources{.jobs = &tracker}, streams, WebRequest{"GET", {"jobs", job->job_id(), "events"}, ""});
  ASSERT_EQ(reply.status, 200);
  Collected out;
  std::future<void> running = RunStream(reply, out);
  EXPECT_TRUE(WaitFor([&] { return out.Has(": keep-alive\n\n"); }));
  // A client that stopped reading: the keep-alive's write fails and the stream ends.
  out.write_ok = false;
  EXPECT_EQ(running.wait_for(5s), std::future_status::ready);
  EXPECT_EQ(streams->open(), 1);  // the reply still holds its place until it goes
}

}  // namespace
}  // namespace vscan::web
