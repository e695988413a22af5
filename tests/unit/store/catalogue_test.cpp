#include "store/catalogue.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <set>
#include <thread>

#include "store/catalogue_schema.h"
#include "vscan_test/temp_dir.h"
#include "sqlite_query.h"

namespace vscan::store {
namespace {

using test::QueryInt;

MeshRecord SampleMesh(const std::string& name, const std::string& sha256) {
  MeshRecord mesh;
  mesh.name = name;
  mesh.sha256 = sha256;
  mesh.vertex_count = 8146;
  mesh.triangle_count = 16301;
  mesh.bounds_min = {-0.0945716, 0.0333891, -0.0618736};
  mesh.bounds_max = {0.0609346, 0.186643, 0.0586895};
  mesh.source_unit = LengthUnit::kCentimetre;
  mesh.source_scale = 0.0254;
  return mesh;
}

Eigen::Matrix4d SamplePose(double seed) {
  Eigen::Matrix4d pose;
  for (int i = 0; i < 16; ++i) pose.data()[i] = std::sin(seed + i) * std::pow(10.0, i % 7 - 3);
  pose(3, 3) = 1;
  return pose;
}

ObjectRecord SampleObject(const std::string& scene_id, const std::string& mesh_id, double seed) {
  ObjectRecord object;
  object.scene_id = scene_id;
  object.mesh_id = mesh_id;
  object.label = "part " + std::to_string(seed);
  object.pose = SamplePose(seed);
  object.scale = 1.5;
  object.on_table = true;
  return object;
}

void ExpectSameMesh(const MeshRecord& a, const MeshRecord& b) {
  EXPECT_EQ(a.mesh_id, b.mesh_id);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.sha256, b.sha256);
  EXPECT_EQ(a.vertex_count, b.vertex_count);
  EXPECT_EQ(a.triangle_count, b.triangle_count);
  EXPECT_EQ(a.bounds_min, b.bounds_min);
  EXPECT_EQ(a.bounds_max, b.bounds_max);
  EXPECT_EQ(a.source_unit, b.source_unit);
  EXPECT_EQ(a.source_scale, b.source_scale);
  EXPECT_EQ(a.create_time_ms, b.create_time_ms);
}

void ExpectSameObject(const ObjectRecord& a, const ObjectRecord& b) {
  EXPECT_EQ(a.object_id, b.object_id);
  EXPECT_EQ(a.scene_id, b.scene_id);
  EXPECT_EQ(a.mesh_id, b.mesh_id);
  EXPECT_EQ(a.label, b.label);
  EXPECT_EQ(a.pose, b.pose);  // bit-exact: stored as raw doubles
  EXPECT_EQ(a.scale, b.scale);
  EXPECT_EQ(a.on_table, b.on_table);
  EXPECT_EQ(a.instance_id, b.instance_id);
}

void ExpectStatus(const Status& status, StatusCode code, const std::string& prefix) {
  EXPECT_EQ(status.code(), code) << status.ToString();
  EXPECT_EQ(status.message().rfind(prefix, 0), 0u) << "message: " << status.message();
}

class CatalogueTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(dir_.path().empty());
    Reopen();
  }
  void Reopen() {
    catalogue_.reset();
    auto opened = Catalogue::Open(db_path());
    ASSERT_TRUE(opened.ok()) << opened.status().ToString();
    catalogue_ = std::move(opened).value();
  }
  std::filesystem::path db_path() const { return dir_.path() / "state" / "catalogue.db"; }

  MeshRecord AddMesh(const std::string& name = "bunny", const std::string& sha = std::string(64, 'a')) {
    auto mesh = catalogue_->InsertMesh(SampleMesh(name, sha));
    EXPECT_TRUE(mesh.ok()) << mesh.status().ToString();
    return mesh.ok() ? *mesh : MeshRecord{};
  }
  SceneRecord AddScene(const std::string& name = "bench") {
    auto scene = catalogue_->CreateScene(name);
    EXPECT_TRUE(scene.ok()) << scene.status().ToString();
    return scene.ok() ? *scene : SceneRecord{};
  }
  uint64_t RevisionOf(const std::string& scene_id) {
    auto scene = catalogue_->GetScene(scene_id);
    return scene.ok() ? scene->revision : 0;
  }

  test::TempDir dir_;
  std::unique_ptr<Catalogue> catalogue_;
};

TEST_F(CatalogueTest, UsesWalAndRecordsTheSchemaVersion) {
  EXPECT_EQ(QueryInt(db_path(), "PRAGMA user_version"), kSchemaVersion);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db_path().c_str(), &db), SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &stmt, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)), "wal");
  sqlite3_finalize(stmt);
  sqlite3_close(db);
}

TEST_F(CatalogueTest, RefusesANewerSchema) {
  catalogue_.reset();
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db_path().c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "PRAGMA user_version = 99", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  auto opened = Catalogue::Open(db_path());
  ASSERT_FALSE(opened.ok());
  EXPECT_EQ(opened.status().code(), StatusCode::kFailedPrecondition) << opened.status().ToString();
}

TEST_F(CatalogueTest, MeshInsertGetAndIds) {
  MeshRecord inserted = AddMesh();
  EXPECT_TRUE(std::regex_match(inserted.mesh_id, std::regex("msh_[0-9a-f]{16}"))) << inserted.mesh_id;
  EXPECT_GT(inserted.create_time_ms, 0);
  auto fetched = catalogue_->GetMesh(inserted.mesh_id);
  ASSERT_TRUE(fetched.ok()) << fetched.status().ToString();
  ExpectSameMesh(*fetched, inserted);

  ExpectStatus(catalogue_->GetMesh("msh_0000000000000000").status(), StatusCode::kNotFound,
               "mesh_id: no mesh 'msh_0000000000000000'");
}

TEST_F(CatalogueTest, ListMeshesPagesInIdOrder) {
  std::vector<std::string> ids;
  for (int i = 0; i < 7; ++i) ids.push_back(AddMesh("m" + std::to_string(i)).mesh_id);
  std::sort(ids.begin(), ids.end());

  std::vector<std::string> seen;
  std::string after;
  for (;;) {
    auto page = catalogue_->ListMeshes(after, 3);
    ASSERT_TRUE(page.ok()) << page.status().ToString();
    ASSERT_LE(page->size(), 3u);
    if (page->empty()) break;
    for (const auto& mesh : *page) seen.push_back(mesh.mesh_id);
    after = page->back().mesh_id;
  }
  EXPECT_EQ(seen, ids);
  EXPECT_EQ(catalogue_->ListMeshes("", 0).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(CatalogueTest, DeleteMeshReportsWhetherTheBlobIsShared) {
  MeshRecord a = AddMesh("a", std::string(64, 'b'));
  MeshRecord b = AddMesh("b", std::string(64, 'b'));
  auto first = catalogue_->DeleteMesh(a.mesh_id);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_EQ(first->first, std::string(64, 'b'));
  EXPECT_FALSE(first->second);
  auto second = catalogue_->DeleteMesh(b.mesh_id);
  ASSERT_TRUE(second.ok());
  EXPECT_TRUE(second->second);
  EXPECT_EQ(catalogue_->GetMesh(a.mesh_id).status().code(), StatusCode::kNotFound);
  ExpectStatus(catalogue_->DeleteMesh(a.mesh_id).status(), StatusCode::kNotFound, "mesh_id: ");
}

TEST_F(CatalogueTest, DeletingAMeshInUseFailsAndChangesNothing) {
  MeshRecord mesh = AddMesh();
  SceneRecord scene = AddScene();
  ASSERT_TRUE(catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, 1)).ok());
  ASSERT_TRUE(catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, 2)).ok());
  ExpectStatus(catalogue_->DeleteMesh(mesh.mesh_id).status(), StatusCode::kFailedPrecondition,
               "mesh_id: mesh '" + mesh.mesh_id + "' is used by 2 objects");
  EXPECT_TRUE(catalogue_->GetMesh(mesh.mesh_id).ok());
}

TEST_F(CatalogueTest, SceneStartsAtRevisionOne) {
  SceneRecord scene = AddScene("it's a \"scene\"; DROP TABLE scenes; --");
  EXPECT_TRUE(std::regex_match(scene.scene_id, std::regex("scn_[0-9a-f]{16}"))) << scene.scene_id;
  EXPECT_EQ(scene.revision, 1u);
  EXPECT_GT(scene.create_time_ms, 0);
  EXPECT_EQ(scene.update_time_ms, scene.create_time_ms);

  auto fetched = catalogue_->GetScene(scene.scene_id);
  ASSERT_TRUE(fetched.ok()) << fetched.status().ToString();
  EXPECT_EQ(fetched->name, "it's a \"scene\"; DROP TABLE scenes; --");
  EXPECT_EQ(fetched->revision, 1u);
  EXPECT_FALSE(fetched->table.enabled);
  EXPECT_EQ(fetched->table.axis, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(fetched->objects.empty());
  ExpectStatus(catalogue_->GetScene("scn_x").status(), StatusCode::kNotFound, "scene_id: no scene 'scn_x'");
}

TEST_F(CatalogueTest, ObjectsGetInstanceIdsAndEveryChangeBumpsTheRevision) {
  MeshRecord mesh = AddMesh();
  SceneRecord scene = AddScene();
  SceneRecord other = AddScene("other");

  std::vector<ObjectRecord> added;
  for (int i = 0; i < 3; ++i) {
    auto result = catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, i));
    ASSERT_TRUE(result.ok()) << result.status().ToString();
    EXPECT_TRUE(std::regex_match(result->first.object_id, std::regex("obj_[0-9a-f]{16}")));
    EXPECT_EQ(result->first.instance_id, static_cast<uint32_t>(i + 1));
    EXPECT_EQ(result->second, static_cast<uint64_t>(i + 2));
    added.push_back(result->first);
  }
  auto in_other = catalogue_->AddObject(SampleObject(other.scene_id, mesh.mesh_id, 9));
  ASSERT_TRUE(in_other.ok());
  EXPECT_EQ(in_other->first.instance_id, 1u);

  auto moved = catalogue_->MoveObject(scene.scene_id, added[1].object_id, SamplePose(42), std::nullopt);
  ASSERT_TRUE(moved.ok()) << moved.status().ToString();
  EXPECT_EQ(moved->second, 5u);
  EXPECT_EQ(moved->first.pose, SamplePose(42));
  EXPECT_EQ(moved->first.scale, 1.5);
  auto rescaled = catalogue_->MoveObject(scene.scene_id, added[1].object_id, SamplePose(43), 0.25);
  ASSERT_TRUE(rescaled.ok());
  EXPECT_EQ(rescaled->second, 6u);
  EXPECT_EQ(rescaled->first.scale, 0.25);
  added[1] = rescaled->first;

  auto removed = catalogue_->RemoveObject(scene.scene_id, added[0].object_id);
  ASSERT_TRUE(removed.ok());
  EXPECT_EQ(*removed, 7u);

  TableRecord table{true, {0.1, 0.2, 0.3}, {0, 1, 0}, 37.5};
  auto tabled = catalogue_->SetTable(scene.scene_id, table);
  ASSERT_TRUE(tabled.ok());
  EXPECT_EQ(*tabled, 8u);

  // Instance ids are never reused within a scene.
  auto fourth = catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, 4));
  ASSERT_TRUE(fourth.ok());
  EXPECT_EQ(fourth->first.instance_id, 4u);
  EXPECT_EQ(fourth->second, 9u);

  auto fetched = catalogue_->GetScene(scene.scene_id);
  ASSERT_TRUE(fetched.ok());
  EXPECT_EQ(fetched->revision, 9u);
  EXPECT_GE(fetched->update_time_ms, fetched->create_time_ms);
  EXPECT_TRUE(fetched->table.enabled);
  EXPECT_EQ(fetched->table.centre, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(fetched->table.axis, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(fetched->table.angle_deg, 37.5);
  ASSERT_EQ(fetched->objects.size(), 3u);
  ExpectSameObject(fetched->objects[0], added[1]);
  ExpectSameObject(fetched->objects[1], added[2]);
  ExpectSameObject(fetched->objects[2], fourth->first);
  EXPECT_EQ(RevisionOf(other.scene_id), 2u);
}

TEST_F(CatalogueTest, UnknownIdsAreNotFoundAndChangeNothing) {
  MeshRecord mesh = AddMesh();
  SceneRecord scene = AddScene();
  auto object = catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, 0));
  ASSERT_TRUE(object.ok());
  const std::string& object_id = object->first.object_id;

  ExpectStatus(catalogue_->AddObject(SampleObject("scn_missing", mesh.mesh_id, 1)).status(), StatusCode::kNotFound,
               "scene_id: no scene 'scn_missing'");
  ExpectStatus(catalogue_->AddObject(SampleObject(scene.scene_id, "msh_missing", 1)).status(), StatusCode::kNotFound,
               "mesh_id: no mesh 'msh_missing'");
  ExpectStatus(catalogue_->MoveObject(scene.scene_id, "obj_missing", SamplePose(1), std::nullopt).status(),
               StatusCode::kNotFound, "object_id: ");
  ExpectStatus(catalogue_->MoveObject("scn_missing", object_id, SamplePose(1), std::nullopt).status(),
               StatusCode::kNotFound, "scene_id: ");
  ExpectStatus(catalogue_->RemoveObject(scene.scene_id, "obj_missing").status(), StatusCode::kNotFound, "object_id: ");
  ExpectStatus(catalogue_->SetTable("scn_missing", TableRecord{}).status(), StatusCode::kNotFound, "scene_id: ");
  ExpectStatus(catalogue_->DeleteScene("scn_missing"), StatusCode::kNotFound, "scene_id: ");

  // An object is addressed through its own scene only.
  SceneRecord other = AddScene("other");
  ExpectStatus(catalogue_->RemoveObject(other.scene_id, object_id).status(), StatusCode::kNotFound, "object_id: ");

  // Failed mutations roll back: no revision bump and no instance id consumed.
  EXPECT_EQ(RevisionOf(scene.scene_id), 2u);
  EXPECT_EQ(RevisionOf(other.scene_id), 1u);
  auto next = catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, 2));
  ASSERT_TRUE(next.ok());
  EXPECT_EQ(next->first.instance_id, 2u);
}

TEST_F(CatalogueTest, InvalidValuesAreRejected) {
  MeshRecord mesh = AddMesh();
  SceneRecord scene = AddScene();
  ObjectRecord bad = SampleObject(scene.scene_id, mesh.mesh_id, 0);
  bad.pose(1, 3) = std::nan("");
  ExpectStatus(catalogue_->AddObject(bad).status(), StatusCode::kInvalidArgument, "pose: ");
  bad = SampleObject(scene.scene_id, mesh.mesh_id, 0);
  bad.scale = 0;
  ExpectStatus(catalogue_->AddObject(bad).status(), StatusCode::kInvalidArgument, "scale: ");
  TableRecord table;
  table.axis.setZero();
  ExpectStatus(catalogue_->SetTable(scene.scene_id, table).status(), StatusCode::kInvalidArgument, "table.axis: ");
  EXPECT_EQ(RevisionOf(scene.scene_id), 1u);
}

TEST_F(CatalogueTest, ObjectsThatWouldLeaveTheWorldBoundsAreRejected) {
  MeshRecord mesh = AddMesh();
  SceneRecord scene = AddScene();
  ObjectRecord far_away = SampleObject(scene.scene_id, mesh.mesh_id, 0);
  far_away.pose = Eigen::Matrix4d::Identity();
  far_away.pose(0, 3) = 1e39;
  ExpectStatus(catalogue_->AddObject(far_away).status(), StatusCode::kInvalidArgument, "pose translation: ");
  // A bunny-sized box scaled by 1e6 reaches about 190 km.
  ObjectRecord huge = SampleObject(scene.scene_id, mesh.mesh_id, 0);
  huge.pose = Eigen::Matrix4d::Identity();
  huge.scale = 1e6;
  ExpectStatus(catalogue_->AddObject(huge).status(), StatusCode::kInvalidArgument, "scale: ");
  huge.scale = 1e4;
  auto added = catalogue_->AddObject(huge);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  const uint64_t revision = RevisionOf(scene.scene_id);
  ExpectStatus(catalogue_->MoveObject(scene.scene_id, added->first.object_id, huge.pose, 1e6).status(),
               StatusCode::kInvalidArgument, "scale: ");
  Eigen::Matrix4d shifted = huge.pose;
  shifted(2, 3) = 9999;  // in bounds itself, but the scaled mesh then reaches past 1e4 m
  ExpectStatus(catalogue_->MoveObject(scene.scene_id, added->first.object_id, shifted, std::nullopt).status(),
               StatusCode::kInvalidArgument, "scale: ");
  TableRecord table;
  table.centre = {0, 0, 2e4};
  ExpectStatus(catalogue_->SetTable(scene.scene_id, table).status(), StatusCode::kInvalidArgument, "table.centre: ");
  EXPECT_EQ(RevisionOf(scene.scene_id), revision);
}

TEST_F(CatalogueTest, DeleteSceneRemovesItsObjects) {
  MeshRecord mesh = AddMesh();
  SceneRecord doomed = AddScene("doomed");
  SceneRecord kept = AddScene("kept");
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(catalogue_->AddObject(SampleObject(doomed.scene_id, mesh.mesh_id, i)).ok());
  ASSERT_TRUE(catalogue_->AddObject(SampleObject(kept.scene_id, mesh.mesh_id, 7)).ok());

  ASSERT_TRUE(catalogue_->DeleteScene(doomed.scene_id).ok());
  EXPECT_EQ(catalogue_->GetScene(doomed.scene_id).status().code(), StatusCode::kNotFound);
  EXPECT_EQ(QueryInt(db_path(), "SELECT count(*) FROM objects"), 1);
  ExpectStatus(catalogue_->DeleteMesh(mesh.mesh_id).status(), StatusCode::kFailedPrecondition,
               "mesh_id: mesh '" + mesh.mesh_id + "' is used by 1 object");

  ASSERT_TRUE(catalogue_->DeleteScene(kept.scene_id).ok());
  EXPECT_TRUE(catalogue_->DeleteMesh(mesh.mesh_id).ok());
  EXPECT_EQ(QueryInt(db_path(), "SELECT count(*) FROM objects"), 0);
}

TEST_F(CatalogueTest, ListScenesPagesWithTheirObjects) {
  MeshRecord mesh = AddMesh();
  std::set<std::string> ids;
  for (int i = 0; i < 5; ++i) {
    SceneRecord scene = AddScene("s" + std::to_string(i));
    ids.insert(scene.scene_id);
    for (int k = 0; k < i; ++k) ASSERT_TRUE(catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, k)).ok());
  }
  auto first = catalogue_->ListScenes("", 2);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  ASSERT_EQ(first->size(), 2u);
  auto rest = catalogue_->ListScenes(first->back().scene_id, 100);
  ASSERT_TRUE(rest.ok());
  ASSERT_EQ(rest->size(), 3u);

  std::vector<std::string> listed;
  for (const auto* page : {&*first, &*rest}) {
    for (const auto& scene : *page) {
      listed.push_back(scene.scene_id);
      int expected_objects = scene.name[1] - '0';
      EXPECT_EQ(scene.objects.size(), static_cast<size_t>(expected_objects)) << scene.name;
      EXPECT_EQ(scene.revision, static_cast<uint64_t>(1 + expected_objects));
    }
  }
  EXPECT_EQ(listed, std::vector<std::string>(ids.begin(), ids.end()));
}

TEST_F(CatalogueTest, EverythingSurvivesCloseAndReopen) {
  MeshRecord mesh = AddMesh();
  SceneRecord scene = AddScene("persistent");
  auto object = catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, 3));
  ASSERT_TRUE(object.ok());
  TableRecord table{true, {1, 2, 3}, {0.6, 0, 0.8}, -12.25};
  ASSERT_TRUE(catalogue_->SetTable(scene.scene_id, table).ok());
  auto before = catalogue_->GetScene(scene.scene_id);
  ASSERT_TRUE(before.ok());

  Reopen();

  auto fetched_mesh = catalogue_->GetMesh(mesh.mesh_id);
  ASSERT_TRUE(fetched_mesh.ok()) << fetched_mesh.status().ToString();
  ExpectSameMesh(*fetched_mesh, mesh);
  auto after = catalogue_->GetScene(scene.scene_id);
  ASSERT_TRUE(after.ok()) << after.status().ToString();
  EXPECT_EQ(after->name, "persistent");
  EXPECT_EQ(after->revision, 3u);
  EXPECT_EQ(after->create_time_ms, before->create_time_ms);
  EXPECT_EQ(after->update_time_ms, before->update_time_ms);
  EXPECT_EQ(after->table.centre, table.centre);
  EXPECT_EQ(after->table.axis, table.axis);
  EXPECT_EQ(after->table.angle_deg, table.angle_deg);
  ASSERT_EQ(after->objects.size(), 1u);
  ExpectSameObject(after->objects[0], object->first);

  // Counters continue where they left off.
  auto next = catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, 4));
  ASSERT_TRUE(next.ok());
  EXPECT_EQ(next->first.instance_id, 2u);
  EXPECT_EQ(next->second, 4u);
}

TEST_F(CatalogueTest, ConcurrentAddsGetDistinctInstanceIds) {
  MeshRecord mesh = AddMesh();
  SceneRecord scene = AddScene();
  constexpr int kThreads = 4;
  constexpr int kPerThread = 25;
  std::vector<std::vector<uint32_t>> got(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kPerThread; ++i) {
        auto result = catalogue_->AddObject(SampleObject(scene.scene_id, mesh.mesh_id, i));
        if (result.ok()) got[t].push_back(result->first.instance_id);
      }
    });
  }
  for (auto& thread : threads) thread.join();
  std::set<uint32_t> all;
  for (const auto& ids : got) all.insert(ids.begin(), ids.end());
  EXPECT_EQ(all.size(), static_cast<size_t>(kThreads * kPerThread));
  EXPECT_EQ(*all.begin(), 1u);
  EXPECT_EQ(*all.rbegin(), static_cast<uint32_t>(kThreads * kPerThread));
  EXPECT_EQ(RevisionOf(scene.scene_id), static_cast<uint64_t>(1 + kThreads * kPerThread));
}

}  // namespace
}  // namespace vscan::store
