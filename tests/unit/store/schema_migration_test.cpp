// A database left by the previous release opens with this code: every row survives, the schema
// reaches the current version, and a second open changes nothing.

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "catalogue_v1_fixture.h"
#include "store/catalogue.h"
#include "store/catalogue_schema.h"
#include "store/database.h"
#include "store/job_catalogue.h"
#include "store/robot_catalogue.h"
#include "store/stored_enums.h"
#include "vscan_test/temp_dir.h"
#include "sqlite_query.h"

namespace vscan::store {
namespace {

using test::QueryInt;

class SchemaMigrationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path().c_str(), &db), SQLITE_OK);
    char* error = nullptr;
    const std::string sql(testing::kCatalogueV1);
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
    sqlite3_close(db);
    ASSERT_EQ(QueryInt(path(), "PRAGMA user_version"), 1);
  }
  std::filesystem::path path() const { return dir_.path() / "catalogue.sqlite"; }

  test::TempDir dir_;
};

TEST_F(SchemaMigrationTest, AVersionOneDatabaseUpgradesWithEveryRow) {
  {
    auto database = Database::Open(path());
    ASSERT_TRUE(database.ok()) << database.status().ToString();
    Catalogue catalogue(*database);
    RobotCatalogue robots(*database);
    JobCatalogue jobs(*database);

    auto mesh = catalogue.GetMesh("msh_00000000000000a1");
    ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
    EXPECT_EQ(mesh->name, "bunny");
    EXPECT_EQ(mesh->sha256, std::string(64, 'a'));
    EXPECT_EQ(mesh->vertex_count, 8146u);
    EXPECT_EQ(mesh->triangle_count, 16301u);
    EXPECT_EQ(mesh->bounds_min, Eigen::Vector3d(-0.5, -0.25, 0.0));
    EXPECT_EQ(mesh->bounds_max, Eigen::Vector3d(0.5, 0.25, 0.75));
    EXPECT_EQ(mesh->source_unit, LengthUnit::kMillimetre);
    EXPECT_EQ(mesh->source_scale, 0.001);
    EXPECT_EQ(mesh->create_time_ms, 1700000000000);

    auto scene = catalogue.GetScene("scn_00000000000000b1");
    ASSERT_TRUE(scene.ok()) << scene.status().ToString();
    EXPECT_EQ(scene->name, "desk");
    EXPECT_EQ(scene->revision, 4u);
    EXPECT_TRUE(scene->table.enabled);
    EXPECT_EQ(scene->table.centre, Eigen::Vector3d(0, 0, -0.1));
    EXPECT_EQ(scene->table.angle_deg, 30.0);
    ASSERT_EQ(scene->objects.size(), 1u);
    EXPECT_EQ(scene->objects[0].object_id, "obj_00000000000000c1");
    EXPECT_EQ(scene->objects[0].pose(0, 3), 0.25);
    EXPECT_EQ(scene->objects[0].pose(1, 3), -0.5);
    EXPECT_EQ(scene->objects[0].scale, 1.5);
    EXPECT_TRUE(scene->objects[0].on_table);
    EXPECT_EQ(scene->objects[0].instance_id, 1u);
    // Rows from before materials read as "no material set".
    EXPECT_FALSE(mesh->material.has_value());
    EXPECT_FALSE(scene->objects[0].material.has_value());

    auto robot = robots.GetRobot("rbt_00000000000000d1");
    ASSERT_TRUE(robot.ok()) << robot.status().ToString();
    EXPECT_EQ(robot->bundle_sha256, std::string(64, 'b'));
    ASSERT_EQ(robot->joints.size(), 2u);
    EXPECT_EQ(robot->joints[0].name, "shoulder");
    EXPECT_EQ(robot->joints[0].type, JointKind::kRevolute);
    EXPECT_EQ(robot->joints[0].lower, -3.0);
    EXPECT_EQ(robot->joints[1].type, JointKind::kPrismatic);
    EXPECT_EQ(robot->joints[1].upper, 0.5);
    EXPECT_EQ(robot->reach, 0.85);
    EXPECT_EQ(robot->warnings, std::vector<std::string>{"warn"});

    auto mount = robots.GetMount("mnt_00000000000000e1");
    ASSERT_TRUE(mount.ok()) << mount.status().ToString();
    EXPECT_EQ(mount->scene_id, "scn_00000000000000b1");
    EXPECT_FALSE(mount->tool_offset.has_value());
    EXPECT_TRUE(mount->links_visible);
    EXPECT_EQ(mount->encoder_sigma, (std::vector<double>{0.001, 0.002}));

    auto done = jobs.GetJob("job_00000000000000f1");
    ASSERT_TRUE(done.ok()) << done.status().ToString();
    EXPECT_EQ(done->state, JobState::kSucceeded);
    EXPECT_EQ(done->spec, "\x0a\x03scn");
    EXPECT_EQ(done->steps_done, 2u);
    EXPECT_EQ(done->last_sequence, 5u);
    ASSERT_EQ(done->artifacts.size(), 2u);
    EXPECT_EQ(done->artifacts[0].name, "scan-r00-v00.ply");
    EXPECT_EQ(done->artifacts[0].info, "\x08\x01");
    EXPECT_EQ(done->artifacts[1].sha256, std::string(64, 'a'));
    auto stopped = jobs.GetJob("job_00000000000000f2");
    ASSERT_TRUE(stopped.ok()) << stopped.status().ToString();
    EXPECT_EQ(stopped->state, JobState::kInterrupted);
  }
  EXPECT_EQ(QueryInt(path(), "PRAGMA user_version"), kSchemaVersion);
  EXPECT_EQ(QueryInt(path(), "SELECT count(*) FROM sqlite_master WHERE name = 'jobs_by_state_and_update_time'"), 1);
  for (const char* table : {"meshes", "scenes", "objects", "robots", "mounts", "jobs", "job_artifacts"}) {
    const std::string count = std::string("SELECT count(*) FROM ") + table;
    EXPECT_GE(QueryInt(path(), count.c_str()), 1) << table;
  }
}

// The catalogue as the release before materials leaves it (version 5): the released steps after
// version 1, run as that release ran them.
TEST_F(SchemaMigrationTest, AVersionFiveDatabaseGainsMaterialsAndKeepsItsRows) {
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path().c_str(), &db), SQLITE_OK);
    for (const Migration& step : kMigrations) {
      if (step.version < 2 || step.version > 5) continue;
      char* error = nullptr;
      const std::string sql(step.sql);
      ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
    }
    ASSERT_EQ(sqlite3_exec(db, "PRAGMA user_version = 5", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  ASSERT_EQ(QueryInt(path(), "SELECT count(*) FROM pragma_table_info('meshes') WHERE name LIKE 'material%'"), 0);
  {
    auto database = Database::Open(path());
    ASSERT_TRUE(database.ok()) << database.status().ToString();
    Catalogue catalogue(*database);
    auto mesh = catalogue.GetMesh("msh_00000000000000a1");
    ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
    EXPECT_EQ(mesh->name, "bunny");
    EXPECT_EQ(mesh->triangle_count, 16301u);
    EXPECT_FALSE(mesh->material.has_value());
    auto scene = catalogue.GetScene("scn_00000000000000b1");
    ASSERT_TRUE(scene.ok()) << scene.status().ToString();
    EXPECT_EQ(scene->revision, 4u);
    ASSERT_EQ(scene->objects.size(), 1u);
    EXPECT_EQ(scene->objects[0].scale, 1.5);
    EXPECT_FALSE(scene->objects[0].material.has_value());

    // The new columns take a material on the old rows too.
    MaterialRecord steel;
    steel.preset = "polished-steel";
    auto set = catalogue.SetObjectMaterial("scn_00000000000000b1", "obj_00000000000000c1", steel);
    ASSERT_TRUE(set.ok()) << set.status().ToString();
    EXPECT_EQ(set->second, 5u);
  }
  EXPECT_EQ(QueryInt(path(), "PRAGMA user_version"), kSchemaVersion);
  EXPECT_EQ(QueryInt(path(), "SELECT count(*) FROM pragma_table_info('meshes') WHERE name LIKE 'material%'"), 5);
  EXPECT_EQ(QueryInt(path(), "SELECT count(*) FROM pragma_table_info('objects') WHERE name LIKE 'material%'"), 5);
  EXPECT_EQ(QueryInt(path(), "SELECT count(*) FROM objects WHERE material_preset = 'polished-steel'"), 1);
  EXPECT_EQ(QueryInt(path(), "SELECT count(*) FROM jobs"), 2);
}

TEST_F(SchemaMigrationTest, OpeningAnUpToDateDatabaseAgainChangesNothing) {
  ASSERT_TRUE(Database::Open(path()).ok());
  const int64_t objects = QueryInt(path(), "SELECT count(*) FROM sqlite_master");
  auto again = Database::Open(path());
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(QueryInt(path(), "SELECT count(*) FROM sqlite_master"), objects);
  EXPECT_EQ(QueryInt(path(), "PRAGMA user_version"), kSchemaVersion);
}

TEST_F(SchemaMigrationTest, AnUnknownStoredEnumCodeIsDataLoss) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path().c_str(), &db), SQLITE_OK);
  const char* corrupt =
      "UPDATE jobs SET state = 99 WHERE job_id = 'job_00000000000000f1';"
      "UPDATE meshes SET source_unit = 42;"
      // The first joint's type code (after the count, the name's length and its 8 bytes) becomes 9.
      "UPDATE robots SET joints = X'02000000080000000000000073686f756c646572090000000000000000000008c0"
      "000000000000084000000000000000000500000000000000736c696465030000000000000000000000000000000000e03f"
      "0000000000000000';";
  ASSERT_EQ(sqlite3_exec(db, corrupt, nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);

  auto database = Database::Open(path());
  ASSERT_TRUE(database.ok()) << database.status().ToString();
  Catalogue catalogue(*database);
  RobotCatalogue robots(*database);
  JobCatalogue jobs(*database);
  const Status job = jobs.GetJob("job_00000000000000f1").status();
  EXPECT_EQ(job.code(), StatusCode::kDataLoss);
  EXPECT_NE(job.message().find("jobs.state"), std::string::npos) << job.message();
  EXPECT_EQ(jobs.ListJobs("", 10).status().code(), StatusCode::kDataLoss);
  EXPECT_EQ(jobs.DeleteJob("job_00000000000000f1").status().code(), StatusCode::kDataLoss);
  const Status mesh = catalogue.GetMesh("msh_00000000000000a1").status();
  EXPECT_EQ(mesh.code(), StatusCode::kDataLoss);
  EXPECT_NE(mesh.message().find("meshes.source_unit"), std::string::npos) << mesh.message();
  EXPECT_EQ(catalogue.ListMeshes("", 10).status().code(), StatusCode::kDataLoss);
  const Status robot = robots.GetRobot("rbt_00000000000000d1").status();
  EXPECT_EQ(robot.code(), StatusCode::kDataLoss);
  EXPECT_NE(robot.message().find("shoulder"), std::string::npos) << robot.message();
  // The other rows still read.
  EXPECT_TRUE(jobs.GetJob("job_00000000000000f2").ok());
}

TEST(StoredEnumsTest, CodesRoundTripAndAreTheVersionOneNumbers) {
  EXPECT_EQ(StoredCode(kJobStateCodes, JobState::kQueued), 1);
  EXPECT_EQ(StoredCode(kJobStateCodes, JobState::kInterrupted), 6);
  EXPECT_EQ(StoredCode(kLengthUnitCodes, LengthUnit::kMillimetre), 3);
  EXPECT_EQ(StoredCode(kJointKindCodes, JointKind::kFixed), 4);
  for (int64_t code = -1; code <= 8; ++code) {
    auto state = FromStoredCode(kJobStateCodes, code, "test");
    EXPECT_EQ(state.ok(), code >= 1 && code <= 6) << code;
    if (state.ok()) {
      EXPECT_EQ(StoredCode(kJobStateCodes, *state), code);
    }
  }
}

TEST(SchemaTest, AFreshDatabaseHasEveryTableAtTheCurrentVersion) {
  test::TempDir dir;
  const auto path = dir.path() / "catalogue.sqlite";
  ASSERT_TRUE(Database::Open(path).ok());
  EXPECT_EQ(QueryInt(path, "PRAGMA user_version"), kSchemaVersion);
  EXPECT_EQ(QueryInt(path,
                     "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name IN ('meshes', 'scenes', "
                     "'objects', 'robots', 'mounts', 'jobs', 'job_artifacts', 'clouds')"),
            8);
  EXPECT_EQ(QueryInt(path, "SELECT count(*) FROM pragma_table_info('clouds') WHERE name = 'frame'"), 1);
}

}  // namespace
}  // namespace vscan::store
