// /api/datasets over a dataset directory laid out as a job writes it: which paths inside it are
// served (hostile ones refused before any file is opened, links never followed), what a running
// job's half-written scene shows, and the view's JSON.

#include "web/web_datasets.h"

#include <sys/stat.h>

#include <fstream>

#include <gtest/gtest.h>

#include "api/job/job_tracker.h"
#include "service/datasets/dataset_directories.h"
#include "store/blob_store.h"
#include "store/job_catalogue.h"
#include "vscan/v1/job.pb.h"
#include "vscan_test/temp_dir.h"
#include "web/web_api.h"
#include "web/web_dataset_json.h"

namespace vscan::web {
namespace {

namespace fs = std::filesystem;

void Write(const fs::path& path, std::string_view bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST(DatasetFilePathTest, AcceptsTheLayoutsFiles) {
  for (const char* path : {"train_pbr/000000/gray/000000.png", "train_pbr/000042/mask_visib/000001_000003.png",
                           "train_pbr/000000/scene_gt.json", "models/obj_000001.ply", "models/models_info.json",
                           "dataset.json", "camera_tof-1.json"}) {
    auto parts = CheckDatasetFilePath(path);
    ASSERT_TRUE(parts.ok()) << path << ": " << parts.status().ToString();
  }
  EXPECT_EQ(*CheckDatasetFilePath("train_pbr/000000/gray/000000.png"),
            (std::vector<std::string>{"train_pbr", "000000", "gray", "000000.png"}));
  EXPECT_EQ(DatasetFileType("train_pbr/000000/gray/000000.png"), "image/png");
  EXPECT_EQ(DatasetFileType("dataset.json"), "application/json");
  EXPECT_EQ(DatasetFileType("models/obj_000001.ply"), "application/octet-stream");
}

TEST(DatasetFilePathTest, RefusesHostilePaths) {
  const std::string long_name = std::string(300, 'a') + ".png";
  const std::string long_path = [] {
    std::string path;
    for (int i = 0; i < 40; ++i) path += "abcdefgh/";
    return path + "x.png";
  }();
  const std::string nul = std::string("gray/000000.png\0.json", 21);
  const std::string nul_folder = std::string("gr\0ay/000000.png", 16);
  for (const std::string& path :
       {std::string(""), std::string(".."), std::string("../dataset.json"), std::string("train_pbr/../../../etc/passwd"),
        std::string("train_pbr/000000/../../x.png"), std::string("./dataset.json"), std::string("%2e%2e/x.png"),
        std::string("train_pbr/%2e%2e/%2e%2e/x.png"), std::string("..%2fx.png"), std::string("%2E%2E/x.png"),
        std::string("/etc/passwd"), std::string("/dataset.json"), std::string("train_pbr//000000/gray/000000.png"),
        std::string("gray/"), std::string("gray\\..\\x.png"), std::string(".hidden.png"), std::string("gray/.png"),
        std::string("dataset.json.tmp-shard-0"), std::string("train_pbr/000000.partial/gray/000000.png"),
        std::string("dataset.tar"), std::string("notes.txt"), std::string("x.PNG"), std::string("x.png.png"),
        std::string("gray/000000"), std::string("a b.png"), std::string("~/x.png"), nul, nul_folder, long_name,
        long_path, std::string("a/b/c/d/e/f/g/h/i.png")}) {
    auto parts = CheckDatasetFilePath(path);
    EXPECT_FALSE(parts.ok()) << "'" << path << "'";
    if (!parts.ok()) {
      EXPECT_EQ(parts.status().code(), StatusCode::kInvalidArgument) << path;
      EXPECT_EQ(parts.status().field(), "path") << path;
    }
  }
}

class DatasetFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = dir_.path() / "datasets" / "job_1";
    outside_ = dir_.path() / "outside";
    Write(root_ / "train_pbr/000000/gray/000000.png", "grey bytes");
    Write(outside_ / "secret.png", "secret");
    Write(outside_ / "000000.png", "secret too");
  }

  StatusCode Code(std::string_view path, uint64_t max_bytes = kMaxDatasetFileBytes) {
    return ReadDatasetFile(root_, path, max_bytes).status().code();
  }

  test::TempDir dir_;
  fs::path root_, outside_;
};

TEST_F(DatasetFileTest, ReadsAFileInsideTheRoot) {
  auto bytes = ReadDatasetFile(root_, "train_pbr/000000/gray/000000.png", kMaxDatasetFileBytes);
  ASSERT_TRUE(bytes.ok()) << bytes.status().ToString();
  EXPECT_EQ(*bytes, "grey bytes");
  EXPECT_EQ(Code("train_pbr/000000/gray/000001.png"), StatusCode::kNotFound);
  EXPECT_EQ(Code("../outside/secret.png"), StatusCode::kInvalidArgument);
}

TEST_F(DatasetFileTest, NeverFollowsALink) {
  // A file, a folder and the root itself linked to what lies outside.
  fs::create_symlink(outside_ / "secret.png", root_ / "train_pbr/000000/gray/000001.png");
  fs::create_symlink(outside_, root_ / "train_pbr/000000/depth");
  fs::create_symlink(outside_, root_ / "linked");
  EXPECT_EQ(Code("train_pbr/000000/gray/000001.png"), StatusCode::kNotFound);
  EXPECT_EQ(Code("train_pbr/000000/depth/000000.png"), StatusCode::kNotFound);
  EXPECT_EQ(Code("linked/secret.png"), StatusCode::kNotFound);
  const fs::path linked_root = dir_.path() / "datasets" / "job_2";
  fs::create_symlink(outside_, linked_root);
  EXPECT_EQ(ReadDatasetFile(linked_root, "secret.png", kMaxDatasetFileBytes).status().code(), StatusCode::kNotFound);
  // A link inside the root that stays inside is refused all the same.
  fs::create_symlink(root_ / "train_pbr/000000/gray/000000.png", root_ / "train_pbr/000000/gray/000002.png");
  EXPECT_EQ(Code("train_pbr/000000/gray/000002.png"), StatusCode::kNotFound);
}

TEST_F(DatasetFileTest, RefusesWhatIsNotARegularFileAndWhatIsTooBig) {
  fs::create_directories(root_ / "train_pbr/000000/gray/000003.png");
  EXPECT_EQ(Code("train_pbr/000000/gray/000003.png"), StatusCode::kNotFound);
  // A FIFO: opened without waiting for a writer, then refused.
  ASSERT_EQ(::mkfifo((root_ / "train_pbr/000000/gray/000004.png").c_str(), 0600), 0);
  EXPECT_EQ(Code("train_pbr/000000/gray/000004.png"), StatusCode::kNotFound);
  EXPECT_EQ(Code("train_pbr/000000/gray/000000.png", 9), StatusCode::kResourceExhausted);
  EXPECT_EQ(Code("train_pbr/000000/gray/000000.png", 10), StatusCode::kOk);
}

TEST(DatasetJsonTest, ReadsOneMemberAndWritesItBack) {
  const std::string text = R"({"0":[{"obj_id":1,"cam_t_m2c":[1.5,-2,3e2]}],"1":[{"obj_id":2,"s":"a\"b"}]})";
  auto member = ParseJsonMember(text, "1", "scene_gt.json");
  ASSERT_TRUE(member.ok()) << member.status().ToString();
  ASSERT_TRUE(member->has_value());
  std::string out;
  AppendJson(out, **member);
  EXPECT_EQ(out, R"([{"obj_id":2,"s":"a\"b"}])");
  auto first = ParseJsonMember(text, "0", "scene_gt.json");
  out.clear();
  AppendJson(out, **first);
  EXPECT_EQ(out, R"([{"obj_id":1,"cam_t_m2c":[1.5,-2,300]}])");
  EXPECT_FALSE(ParseJsonMember(text, "2", "x")->has_value());
  for (const char* bad : {"", "{", R"({"0":[1,]})", R"({"0":1} x)", "[1]", R"({"0":tru})"}) {
    EXPECT_EQ(ParseJsonMember(bad, "0", "x").status().code(), StatusCode::kDataLoss) << bad;
  }
  std::string deep(100, '[');
  deep += std::string(100, ']');
  EXPECT_EQ(ParseJson(deep, "x").status().code(), StatusCode::kDataLoss);
}

// The API over a job record and its directory as a running dataset job leaves it: scene 0 complete,
// scene 1 still being written.
class DatasetApiTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto catalogue = store::JobCatalogue::Open(dir_.path() / "jobs.sqlite");
    ASSERT_TRUE(catalogue.ok()) << catalogue.status().ToString();
    catalogue_ = std::move(catalogue).value();
    blobs_ = std::make_unique<store::BlobStore>(dir_.path() / "blobs");
    ASSERT_TRUE(blobs_->Open().ok());
    tracker_ = std::make_unique<api::JobTracker>(*catalogue_, *blobs_);
    directories_ = std::make_unique<service::DatasetDirectories>(dir_.path(), nullptr);
    store::JobRecord job;
    job.kind = "dataset";
    job.name = "bins";
    job.state = store::JobState::kRunning;
    job.spec = v1::DatasetSpec().SerializeAsString();
    auto inserted = catalogue_->InsertJob(job);
    ASSERT_TRUE(inserted.ok()) << inserted.status().ToString();
    job_id_ = inserted->job_id;
    store::JobRecord other;
    other.kind = "campaign";
    other_id_ = catalogue_->InsertJob(other)->job_id;
    root_ = directories_->Root(job_id_);
    Write(root_ / "dataset.json", R"({"format":"vscan-dataset","layout_version":2,"scene_count":3,)"
                                  R"("plan":{"name":"bins","depth_scale_mm":0.1}})");
    Write(root_ / "models/obj_000001.ply", "ply");
    const fs::path scene = root_ / "train_pbr/000000";
    Write(scene / "scene_camera.json",
          R"({"0":{"cam_K":[100,0,79.5,0,100,59.5,0,0,1],"depth_scale":0.1,"width":160,"height":120},)"
          R"("1":{"cam_K":[101,0,79.5,0,101,59.5,0,0,1],"depth_scale":0.1,"width":160,"height":120}})");
    Write(scene / "scene_gt.json", R"({"0":[{"obj_id":1,"instance_id":7,"cam_R_m2c":[1,0,0,0,1,0,0,0,1],)"
                                   R"("cam_t_m2c":[0,0,500]}],"1":[]})");
    Write(scene / "scene_gt_info.json", R"({"0":[{"bbox_obj":[10,20,5,6],"bbox_visib":[11,21,4,5],)"
                                        R"("px_count_all":42,"px_count_valid":30,"px_count_visib":36,)"
                                        R"("visib_fract":0.857}],"1":[]})");
    for (const char* view : {"000000", "000001"}) {
      Write(scene / "depth" / (std::string(view) + ".png"), "depth");
      Write(scene / "gray" / (std::string(view) + ".png"), "grey");
      Write(scene / "instances" / (std::string(view) + ".png"), "instances");
      Write(scene / "cloud" / (std::string(view) + ".ply"), "cloud");
    }
    Write(root_ / "train_pbr/000001.partial/depth/000000.png", "half");
  }

  WebReply Get(std::string_view path, std::string_view query = "") {
    const WebApi api(WebSources{.jobs = tracker_.get(), .datasets = directories_.get()}, WebApiOptions{.token = "t"});
    return api.Handle("GET", path, query, "Bearer t");
  }

  test::TempDir dir_;
  std::unique_ptr<store::JobCatalogue> catalogue_;
  std::unique_ptr<store::BlobStore> blobs_;
  std::unique_ptr<api::JobTracker> tracker_;
  std::unique_ptr<service::DatasetDirectories> directories_;
  std::string job_id_, other_id_;
  fs::path root_;
};

TEST_F(DatasetApiTest, ListsTheDatasetJobsWithTheirCompleteScenes) {
  const WebReply list = Get("/api/datasets");
  ASSERT_EQ(list.status, 200) << list.body;
  EXPECT_EQ(list.content_type, "application/json");
  EXPECT_NE(list.body.find(R"("job_id":")" + job_id_ + R"(","name":"bins","state":"RUNNING")"), std::string::npos)
      << list.body;
  EXPECT_NE(list.body.find(R"("scene_count":3,"scenes_complete":1)"), std::string::npos) << list.body;
  EXPECT_EQ(list.body.find(other_id_), std::string::npos) << list.body;

  const WebReply dataset = Get("/api/datasets/" + job_id_);
  ASSERT_EQ(dataset.status, 200) << dataset.body;
  // Scene 1 is still being written: not listed.
  EXPECT_NE(dataset.body.find(R"("splits":[{"split":"train_pbr","scenes":[{"scene_id":"000000","views":[0,1]}],)"
                              R"("more":false}])"),
            std::string::npos)
      << dataset.body;
  EXPECT_NE(dataset.body.find(R"("models":[{"obj_id":1,"file":"models/obj_000001.ply"}])"), std::string::npos);
  EXPECT_NE(dataset.body.find(R"("depth_scale_mm":0.1)"), std::string::npos);
  EXPECT_NE(Get("/api/datasets/" + job_id_, "after=0").body.find(R"("scenes":[])"), std::string::npos);
  EXPECT_EQ(Get("/api/datasets/" + job_id_, "limit=0").status, 400);
  EXPECT_EQ(Get("/api/datasets/" + job_id_, "after=x").status, 400);

  EXPECT_EQ(Get("/api/datasets/" + other_id_).status, 404);
  EXPECT_EQ(Get("/api/datasets/job_0000000000000000").status, 404);
  EXPECT_EQ(Get("/api/datasets/..").status, 404);
}

TEST_F(DatasetApiTest, AViewsCameraAndGroundTruth) {
  const WebReply view = Get("/api/datasets/" + job_id_ + "/scenes/000000/views/0");
  ASSERT_EQ(view.status, 200) << view.body;
  const std::string prefix = "train_pbr/000000/";
  EXPECT_EQ(view.body,
            R"({"job_id":")" + job_id_ + R"(","split":"train_pbr","scene_id":"000000","view":0,)"
            R"("camera":{"cam_K":[100,0,79.5,0,100,59.5,0,0,1],"depth_scale":0.1,"width":160,"height":120},)"
            R"("objects":[{"gt_index":0,"obj_id":1,"instance_id":7,"cam_R_m2c":[1,0,0,0,1,0,0,0,1],)"
            R"("cam_t_m2c":[0,0,500],"bbox_obj":[10,20,5,6],"bbox_visib":[11,21,4,5],"px_count_all":42,)"
            R"("px_count_valid":30,"px_count_visib":36,"visib_fract":0.857,)"
            R"("mask_visib":")" + prefix + R"(mask_visib/000000_000000.png","mask":")" + prefix +
                R"(mask/000000_000000.png"}],)"
            R"("images":{"gray":")" + prefix + R"(gray/000000.png","depth":")" + prefix +
                R"(depth/000000.png","instances":")" + prefix + R"(instances/000000.png","reasons":null,)"
            R"("cloud":")" + prefix + R"(cloud/000000.ply"}})");
  // The same scene and view by plain numbers; the second view's camera.
  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/0/views/000").body, view.body);
  EXPECT_NE(Get("/api/datasets/" + job_id_ + "/scenes/0/views/1").body.find(R"("cam_K":[101,)"), std::string::npos);

  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/000000/views/2").status, 404);
  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/000001/views/0").status, 404);  // still being written
  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/000000.partial/views/0").status, 400);
  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/-1/views/0").status, 400);
  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/1000000/views/0").status, 400);
  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/0/views/x").status, 400);
  EXPECT_EQ(Get("/api/datasets/" + job_id_ + "/scenes/0/views/1000").status, 400);
}

TEST_F(DatasetApiTest, FilesOnlyUnderTheDatasetsRoot) {
  const std::string files = "/api/datasets/" + job_id_ + "/files/";
  const WebReply grey = Get(files + "train_pbr/000000/gray/000000.png");
  EXPECT_EQ(grey.status, 200);
  EXPECT_EQ(grey.content_type, "image/png");
  EXPECT_EQ(grey.body, "grey");
  EXPECT_EQ(Get(files + "dataset.json").content_type, "application/json");
  EXPECT_EQ(Get(files + "models/obj_000001.ply").content_type, "application/octet-stream");
  Write(dir_.path() / "secret.json", "{}");
  Write(dir_.path() / "datasets/secret.json", "{}");
  fs::create_symlink(dir_.path() / "secret.json", root_ / "train_pbr/000000/link.json");
  for (const std::string& path :
       {std::string("../secret.json"), std::string("../../secret.json"), std::string("%2e%2e/secret.json"),
        std::string("%2e%2e/%2e%2e/secret.json"), std::string("/secret.json"), std::string("//secret.json"),
        std::string("train_pbr/000001.partial/depth/000000.png"), std::string("train_pbr/000000/gray/"),
        std::string("dataset.json.tmp-shard-0"), std::string("jobs.sqlite"), std::string(300, 'a') + ".png",
        std::string("gray/000000.png\0.json", 21)}) {
    const WebReply reply = Get(files + path);
    EXPECT_EQ(reply.status, 400) << path << ": " << reply.body;
    EXPECT_NE(reply.body.find("path"), std::string::npos) << reply.body;
  }
  EXPECT_EQ(Get(files + "train_pbr/000000/link.json").status, 404);
  EXPECT_EQ(Get(files + "train_pbr/000000/gray/000009.png").status, 404);
  EXPECT_EQ(Get("/api/datasets/" + other_id_ + "/files/dataset.json").status, 404);
  // Not the token: nothing, whatever the path.
  const WebApi api(WebSources{.jobs = tracker_.get(), .datasets = directories_.get()}, WebApiOptions{.token = "t"});
  EXPECT_EQ(api.Handle("GET", files + "dataset.json", "", "Bearer u").status, 401);
  EXPECT_EQ(api.Handle("GET", "/api/datasets", "", "").status, 401);
}

TEST_F(DatasetApiTest, NotServedWithoutTheStores) {
  const WebApi api(WebSources{}, WebApiOptions{});
  EXPECT_EQ(api.Handle("GET", "/api/datasets", "", "").status, 404);
}

}  // namespace
}  // namespace vscan::web
