#include "store/cloud_catalogue.h"

#include <algorithm>
#include <array>
#include <utility>

#include "store/byte_codec.h"
#include "store/ids.h"
#include "store/robot_records.h"
#include "store/list_page.h"
#include "store/sqlite_statement.h"
#include "vscan/common/point_cloud.h"

namespace vscan::store {
namespace {

using sqlite::Statement;

constexpr std::string_view kColumns =
    "cloud_id, name, sha256, size_bytes, points, fields, origin, job_id, scene_id, sensor_pose, camera, "
    "table_angle_deg, create_time_ms, frame";

struct FieldName {
  PointFields field;
  std::string_view name;
};
// Part of the file format: a stored name never changes.
constexpr std::array<FieldName, 10> kFieldNames{{
    {kFieldPosition, "position"},
    {kFieldNormal, "normal"},
    {kFieldRange, "range"},
    {kFieldIntensity, "intensity"},
    {kFieldInstanceId, "instance_id"},
    {kFieldPixel, "pixel"},
    {kFieldCleanPosition, "clean_position"},
    {kFieldIncidence, "incidence"},
    {kFieldStatus, "status"},
    {kFieldEstimatedNormal, "estimated_normal"},
}};

std::string EncodeCamera(const CloudCamera& c) {
  ByteWriter w;
  w.U32(c.width);
  w.U32(c.height);
  for (double v : {c.fx, c.fy, c.cx, c.cy, c.near, c.far}) w.F64(v);
  return w.Take();
}

StatusOr<CloudCamera> DecodeCamera(std::string_view bytes, const std::string& cloud_id) {
  ByteReader r(bytes, "clouds.camera of '" + cloud_id + "'");
  CloudCamera c;
  ASSIGN_OR_RETURN(c.width, r.U32());
  ASSIGN_OR_RETURN(c.height, r.U32());
  for (double* v : {&c.fx, &c.fy, &c.cx, &c.cy, &c.near, &c.far}) {
    ASSIGN_OR_RETURN(*v, r.F64());
  }
  return c;
}

StatusOr<CloudRecord> ReadCloud(const Statement& s) {
  CloudRecord c;
  c.cloud_id = s.Text(0);
  c.name = s.Text(1);
  c.sha256 = s.Text(2);
  c.size_bytes = static_cast<uint64_t>(s.Int(3));
  c.points = static_cast<uint64_t>(s.Int(4));
  ASSIGN_OR_RETURN(c.fields, FieldsFromNames(s.Text(5), "clouds.fields of '" + c.cloud_id + "'"));
  ASSIGN_OR_RETURN(c.origin, FromStoredCode(kCloudOriginCodes, s.Int(6), "clouds.origin of '" + c.cloud_id + "'"));
  c.job_id = s.Text(7);
  c.scene_id = s.Text(8);
  if (!s.IsNull(9)) {
    ASSIGN_OR_RETURN(c.world_from_sensor, robot_rows::DecodePose(s.Blob(9), "clouds.sensor_pose"));
  }
  if (!s.IsNull(10)) {
    ASSIGN_OR_RETURN(c.camera, DecodeCamera(s.Blob(10), c.cloud_id));
  }
  if (!s.IsNull(11)) c.table_angle_deg = s.Double(11);
  c.create_time_ms = s.Int(12);
  ASSIGN_OR_RETURN(c.frame, FromStoredCode(kCloudFrameCodes, s.Int(13), "clouds.frame of '" + c.cloud_id + "'"));
  return c;
}

Status CloudNotFound(const std::string& cloud_id) { return NotFound("cloud_id", "no cloud '" + cloud_id + "'"); }

}  // namespace

std::string FieldNames(uint32_t fields) {
  std::string out;
  for (const FieldName& f : kFieldNames) {
    if ((fields & f.field) == 0) continue;
    if (!out.empty()) out += ',';
    out += f.name;
  }
  return out;
}

StatusOr<uint32_t> FieldsFromNames(std::string_view names, std::string_view where) {
  uint32_t fields = 0;
  while (!names.empty()) {
    const size_t comma = names.find(',');
    const std::string_view name = names.substr(0, comma);
    const auto* known = std::find_if(kFieldNames.begin(), kFieldNames.end(),
                                     [&](const FieldName& f) { return f.name == name; });
    if (known == kFieldNames.end()) {
      return DataLoss("catalogue: " + std::string(where) + " names unknown field '" + std::string(name) + "'");
    }
    fields |= known->field;
    names = comma == std::string_view::npos ? std::string_view() : names.substr(comma + 1);
  }
  return fields;
}

CloudCatalogue::CloudCatalogue(std::shared_ptr<Database> database) : database_(std::move(database)) {}

StatusOr<std::unique_ptr<CloudCatalogue>> CloudCatalogue::Open(const std::filesystem::path& db_path) {
  ASSIGN_OR_RETURN(std::shared_ptr<Database> database, Database::Open(db_path));
  return std::make_unique<CloudCatalogue>(std::move(database));
}

Status InsertCloudRow(sqlite3* db, CloudRecord& cloud) {
  if (cloud.origin == CloudOrigin::kCampaignScan && cloud.job_id.empty()) {
    return InvalidArgument("job_id", "required for a campaign's scan");
  }
  cloud.cloud_id = NewId("cld_");
  cloud.create_time_ms = NowMs();
  std::string sql = "INSERT INTO clouds (";
  sql.append(kColumns).append(") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)");
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db, sql));
  s.Bind(1, cloud.cloud_id).Bind(2, cloud.name).Bind(3, cloud.sha256);
  s.Bind(4, static_cast<int64_t>(cloud.size_bytes)).Bind(5, static_cast<int64_t>(cloud.points));
  s.Bind(6, FieldNames(cloud.fields)).Bind(7, StoredCode(kCloudOriginCodes, cloud.origin));
  if (cloud.job_id.empty()) {
    s.BindNull(8);
  } else {
    s.Bind(8, cloud.job_id);
  }
  s.Bind(9, cloud.scene_id);
  if (cloud.world_from_sensor) {
    s.BindBlob(10, robot_rows::EncodePose(*cloud.world_from_sensor));
  } else {
    s.BindNull(10);
  }
  if (cloud.camera) {
    s.BindBlob(11, EncodeCamera(*cloud.camera));
  } else {
    s.BindNull(11);
  }
  if (cloud.table_angle_deg) {
    s.Bind(12, *cloud.table_angle_deg);
  } else {
    s.BindNull(12);
  }
  s.Bind(13, cloud.create_time_ms).Bind(14, StoredCode(kCloudFrameCodes, cloud.frame));
  return s.Run();
}

StatusOr<CloudRecord> CloudCatalogue::Insert(CloudRecord cloud) {
  std::lock_guard lock(database_->mutex());
  sqlite3* db = database_->handle();
  RETURN_IF_ERROR(sqlite::InTransaction(db, true, [&] { return InsertCloudRow(db, cloud); }));
  return cloud;
}

StatusOr<CloudRecord> CloudCatalogue::Get(const std::string& cloud_id) {
  std::lock_guard lock(database_->mutex());
  std::string sql = "SELECT ";
  sql.append(kColumns).append(" FROM clouds WHERE cloud_id = ?1");
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(database_->handle(), sql));
  s.Bind(1, cloud_id);
  ASSIGN_OR_RETURN(const bool row, s.Step());
  if (!row) return CloudNotFound(cloud_id);
  return ReadCloud(s);
}

StatusOr<std::vector<CloudRecord>> CloudCatalogue::List(const std::string& after_id, int limit,
                                                        const std::string& job_id) {
  if (limit <= 0) return InvalidArgument("limit", "must be positive, got " + std::to_string(limit));
  std::lock_guard lock(database_->mutex());
  std::string sql = "SELECT ";
  sql.append(kColumns).append(" FROM clouds WHERE cloud_id > ?1 AND (?2 = '' OR job_id = ?2) ORDER BY cloud_id LIMIT ?3");
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(database_->handle(), sql));
  s.Bind(1, after_id).Bind(2, job_id).Bind(3, int64_t{std::min(limit, kMaxListLimit)});
  std::vector<CloudRecord> clouds;
  for (;;) {
    ASSIGN_OR_RETURN(const bool row, s.Step());
    if (!row) return clouds;
    ASSIGN_OR_RETURN(CloudRecord cloud, ReadCloud(s));
    clouds.push_back(std::move(cloud));
  }
}

StatusOr<std::string> CloudCatalogue::Delete(const std::string& cloud_id) {
  std::lock_guard lock(database_->mutex());
  sqlite3* db = database_->handle();
  std::string sha256;
  RETURN_IF_ERROR(sqlite::InTransaction(db, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement find, Statement::Prepare(db, "SELECT sha256, job_id FROM clouds WHERE cloud_id = ?1"));
    find.Bind(1, cloud_id);
    ASSIGN_OR_RETURN(const bool found, find.Step());
    if (!found) return CloudNotFound(cloud_id);
    if (!find.IsNull(1)) {
      return FailedPrecondition("cloud_id", "cloud '" + cloud_id + "' is a scan of job '" + find.Text(1) +
                                "'; it goes when the job is deleted");
    }
    sha256 = find.Text(0);
    ASSIGN_OR_RETURN(Statement del, Statement::Prepare(db, "DELETE FROM clouds WHERE cloud_id = ?1"));
    del.Bind(1, cloud_id);
    return del.Run();
  }));
  return sha256;
}

}  // namespace vscan::store
