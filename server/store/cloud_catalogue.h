#pragma once
// Point clouds as stored resources: the clouds clients upload and the scans campaigns capture.
// The points live in a blob (binary PLY); the row says what they are and, when known, where the
// sensor stood. A campaign's clouds go with their job. Thread-safe: shares the Database's one
// connection and its lock.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "store/database.h"
#include "store/stored_enums.h"
#include "vscan/common/status.h"

struct sqlite3;

namespace vscan::store {

// The pinhole camera of a scan, for methods that need its image (volumetric fusion).
struct CloudCamera {
  uint32_t width = 0;
  uint32_t height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double near = 0, far = 0;
};

struct CloudRecord {
  std::string cloud_id;
  std::string name;
  std::string sha256;  // blob holding the binary PLY
  uint64_t size_bytes = 0;
  uint64_t points = 0;
  uint32_t fields = 0;  // PointFields bits; stored by name
  CloudOrigin origin = CloudOrigin::kUploaded;
  std::string job_id;    // the campaign that captured it; empty for uploads
  std::string scene_id;  // the scene it was scanned in, when known
  // The frame the points are in; world_from_sensor says where the sensor stood either way.
  CloudFrame frame = CloudFrame::kWorld;
  std::optional<Eigen::Matrix4d> world_from_sensor;
  std::optional<CloudCamera> camera;
  std::optional<double> table_angle_deg;
  int64_t create_time_ms = 0;
};

class CloudCatalogue {
 public:
  explicit CloudCatalogue(std::shared_ptr<Database> database);
  // Opens or creates the database file with its own Database (tests and tools).
  static StatusOr<std::unique_ptr<CloudCatalogue>> Open(const std::filesystem::path& db_path);
  Database& database() { return *database_; }

  // The id is generated ("cld_" + 16 hex digits); the blob it names must already be durable.
  StatusOr<CloudRecord> Insert(CloudRecord cloud);
  StatusOr<CloudRecord> Get(const std::string& cloud_id);
  // Ordered by id; ids greater than after_id; only job_id's clouds when it is set; at most limit.
  StatusOr<std::vector<CloudRecord>> List(const std::string& after_id, int limit, const std::string& job_id = "");
  // Returns the blob the cloud named (to collect); NOT_FOUND for an unknown cloud,
  // FAILED_PRECONDITION for a campaign's cloud (it goes with its job).
  StatusOr<std::string> Delete(const std::string& cloud_id);

 private:
  std::shared_ptr<Database> database_;
};

// Inserts cloud's row (id and time generated) inside a transaction of the caller, who holds the
// Database's lock: a campaign's scan is recorded in the transaction that records its artifact.
Status InsertCloudRow(sqlite3* db, CloudRecord& cloud);

// The stored spelling of fields ("position,normal,range"), and back (DATA_LOSS naming where for a
// name no field has).
std::string FieldNames(uint32_t fields);
StatusOr<uint32_t> FieldsFromNames(std::string_view names, std::string_view where);

}  // namespace vscan::store
