#pragma once
// The durable record of robots and of their mounts in scenes. Lives in the catalogue's SQLite file
// (shared through Database); a mount goes when its scene goes.
// Every mutation is one transaction; mounting and unmounting bump the scene's revision.
// Thread-safe: shares the Database's one connection and its lock.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "store/database.h"
#include "store/stored_enums.h"
#include "vscan/common/status.h"

struct sqlite3;

namespace vscan::store {

struct JointRecord {
  std::string name;
  JointKind type = JointKind::kRevolute;
  double lower = 0.0;
  double upper = 0.0;
  double max_velocity = 0.0;
};

struct RobotRecord {
  std::string robot_id;
  std::string name;
  std::string urdf_path;  // normalised, inside the bundle
  std::string base_link;
  std::string tip_link;
  Eigen::Matrix4d tool_offset = Eigen::Matrix4d::Identity();  // tip_from_tool
  std::string bundle_sha256;                                  // blob holding the encoded bundle
  uint64_t bundle_bytes = 0;
  uint32_t file_count = 0;
  std::vector<JointRecord> joints;  // movable joints, base to tip
  double reach = 0.0;
  std::vector<std::string> warnings;
  int64_t create_time_ms = 0;
};

struct MountRecord {
  std::string mount_id;
  std::string scene_id;
  std::string robot_id;
  Eigen::Matrix4d base_pose = Eigen::Matrix4d::Identity();  // world_from_base
  std::optional<Eigen::Matrix4d> tool_offset;               // tip_from_sensor; unset: the robot's
  bool links_visible = false;
  std::vector<double> encoder_sigma;  // empty, or one per joint
  int64_t create_time_ms = 0;
};

class RobotCatalogue {
 public:
  explicit RobotCatalogue(std::shared_ptr<Database> database);
  // Opens or creates the database file with its own Database (tests and tools).
  static StatusOr<std::unique_ptr<RobotCatalogue>> Open(const std::filesystem::path& db_path);
  Database& database() { return *database_; }

  // ids are generated ("rbt_" + 16 hex digits).
  StatusOr<RobotRecord> InsertRobot(RobotRecord robot);
  StatusOr<RobotRecord> GetRobot(const std::string& robot_id);
  // Ordered by id; ids greater than after_id; at most limit (1..1000). The same for ListMounts.
  StatusOr<std::vector<RobotRecord>> ListRobots(const std::string& after_id, int limit);
  // FAILED_PRECONDITION while mounted. Returns the bundle's sha256 and whether no other robot
  // shares it (the blob may go then).
  StatusOr<std::pair<std::string, bool>> DeleteRobot(const std::string& robot_id);

  // ids "mnt_" + 16 hex. NOT_FOUND for an unknown scene or robot. Returns the scene's new revision.
  StatusOr<std::pair<MountRecord, uint64_t>> InsertMount(MountRecord mount);
  StatusOr<MountRecord> GetMount(const std::string& mount_id);
  // Every scene's mounts when scene_id is empty; NOT_FOUND for an unknown scene.
  StatusOr<std::vector<MountRecord>> ListMounts(const std::string& scene_id, const std::string& after_id, int limit);
  // Returns the scene's new revision.
  StatusOr<uint64_t> DeleteMount(const std::string& mount_id);

 private:
  std::shared_ptr<Database> database_;
  std::mutex& mutex_;
  sqlite3* db_;
};

}  // namespace vscan::store
