#include "store/catalogue.h"
#include "store/ids.h"


#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <utility>

#include "store/list_page.h"
#include "store/material_columns.h"
#include "store/sqlite_statement.h"
#include "vscan/common/physical_limits.h"

namespace vscan::store {
namespace {

using sqlite::Statement;

constexpr std::string_view kMeshColumns =
    "mesh_id, name, sha256, vertex_count, triangle_count, min_x, min_y, min_z, max_x, max_y, max_z, "
    "source_unit, source_scale, create_time_ms, material_preset, material_albedo, material_metallic, "
    "material_roughness, material_specular";
constexpr std::string_view kSceneColumns =
    "scene_id, name, revision, table_enabled, table_centre_x, table_centre_y, table_centre_z, "
    "table_axis_x, table_axis_y, table_axis_z, table_angle_deg, create_time_ms, update_time_ms";
constexpr std::string_view kObjectColumns =
    "object_id, scene_id, mesh_id, label, pose, scale, on_table, instance_id, material_preset, material_albedo, "
    "material_metallic, material_roughness, material_specular";

// Joins fixed SQL fragments; values always travel as bound parameters.
std::string Sql(std::string_view a, std::string_view b, std::string_view c) {
  std::string sql(a);
  sql.append(b).append(c);
  return sql;
}

// 16 little-endian doubles, column-major.
std::string EncodePose(const Eigen::Matrix4d& pose) {
  std::string bytes(128, '\0');
  for (int i = 0; i < 16; ++i) {
    auto bits = std::bit_cast<uint64_t>(pose.data()[i]);
    for (int b = 0; b < 8; ++b) bytes[8 * i + b] = static_cast<char>((bits >> (8 * b)) & 0xff);
  }
  return bytes;
}

StatusOr<Eigen::Matrix4d> DecodePose(std::string_view bytes) {
  if (bytes.size() != 128) return DataLoss("catalogue: stored pose has " + std::to_string(bytes.size()) + " bytes");
  Eigen::Matrix4d pose;
  for (int i = 0; i < 16; ++i) {
    uint64_t bits = 0;
    for (int b = 0; b < 8; ++b) bits |= uint64_t{static_cast<unsigned char>(bytes[8 * i + b])} << (8 * b);
    pose.data()[i] = std::bit_cast<double>(bits);
  }
  return pose;
}

StatusOr<MeshRecord> ReadMesh(const Statement& s) {
  MeshRecord m;
  m.mesh_id = s.Text(0);
  m.name = s.Text(1);
  m.sha256 = s.Text(2);
  m.vertex_count = static_cast<uint64_t>(s.Int(3));
  m.triangle_count = static_cast<uint64_t>(s.Int(4));
  m.bounds_min = {s.Double(5), s.Double(6), s.Double(7)};
  m.bounds_max = {s.Double(8), s.Double(9), s.Double(10)};
  ASSIGN_OR_RETURN(m.source_unit, FromStoredCode(kLengthUnitCodes, s.Int(11), "meshes.source_unit of '" + m.mesh_id + "'"));
  m.source_scale = s.Double(12);
  m.create_time_ms = s.Int(13);
  ASSIGN_OR_RETURN(m.material, ReadMaterial(s, 14, "mesh '" + m.mesh_id + "'"));
  return m;
}

SceneRecord ReadScene(const Statement& s) {
  SceneRecord scene;
  scene.scene_id = s.Text(0);
  scene.name = s.Text(1);
  scene.revision = static_cast<uint64_t>(s.Int(2));
  scene.table.enabled = s.Int(3) != 0;
  scene.table.centre = {s.Double(4), s.Double(5), s.Double(6)};
  scene.table.axis = {s.Double(7), s.Double(8), s.Double(9)};
  scene.table.angle_deg = s.Double(10);
  scene.create_time_ms = s.Int(11);
  scene.update_time_ms = s.Int(12);
  return scene;
}

StatusOr<ObjectRecord> ReadObject(const Statement& s) {
  ObjectRecord o;
  o.object_id = s.Text(0);
  o.scene_id = s.Text(1);
  o.mesh_id = s.Text(2);
  o.label = s.Text(3);
  ASSIGN_OR_RETURN(o.pose, DecodePose(s.Blob(4)));
  o.scale = s.Double(5);
  o.on_table = s.Int(6) != 0;
  o.instance_id = static_cast<uint32_t>(s.Int(7));
  ASSIGN_OR_RETURN(o.material, ReadMaterial(s, 8, "object '" + o.object_id + "'"));
  return o;
}

Status CheckLimit(int limit) {
  if (limit <= 0) return InvalidArgument("limit", "must be positive, got " + std::to_string(limit));
  return Status::Ok();
}

Status CheckPose(const Eigen::Matrix4d& pose) {
  if (!pose.allFinite()) return InvalidArgument("pose: every element must be finite");
  return CheckPosition(pose.topRightCorner<3, 1>(), "pose translation");
}

Status CheckTable(const TableRecord& table) {
  RETURN_IF_ERROR(CheckPosition(table.centre, "table.centre"));
  if (!table.axis.allFinite() || table.axis.norm() == 0) {
    return InvalidArgument("table.axis: must be finite and non-zero");
  }
  if (!std::isfinite(table.angle_deg)) return InvalidArgument("table.angle_deg: must be finite");
  return Status::Ok();
}

Status SceneNotFound(const std::string& scene_id) { return NotFound("scene_id: no scene '" + scene_id + "'"); }
Status MeshNotFound(const std::string& mesh_id) { return NotFound("mesh_id: no mesh '" + mesh_id + "'"); }

// The mesh's box, scaled and placed, must stay within the bounds where meshes may lie.
Status CheckPlacement(sqlite3* db, const std::string& mesh_id, const Eigen::Matrix4d& pose, double scale) {
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db, "SELECT min_x, min_y, min_z, max_x, max_y, max_z "
                                                       "FROM meshes WHERE mesh_id = ?1"));
  s.Bind(1, mesh_id);
  ASSIGN_OR_RETURN(bool found, s.Step());
  if (!found) return MeshNotFound(mesh_id);
  const Eigen::Vector3d lo(s.Double(0), s.Double(1), s.Double(2)), hi(s.Double(3), s.Double(4), s.Double(5));
  double reach = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d local((corner & 1 ? hi : lo).x(), (corner & 2 ? hi : lo).y(), (corner & 4 ? hi : lo).z());
    const Eigen::Vector3d world = pose.topLeftCorner<3, 3>() * (scale * local) + pose.topRightCorner<3, 1>();
    reach = std::max(reach, world.cwiseAbs().maxCoeff());
  }
  if (!(reach <= kMaxMeshCoordinateM)) {
    return InvalidArgument("scale: mesh '" + mesh_id + "' placed at this pose and scale reaches " +
                           std::to_string(reach) + " m from the origin; objects must lie within 1e4 m");
  }
  return Status::Ok();
}

Status CheckScale(double scale) {
  if (!std::isfinite(scale) || scale <= 0) {
    return InvalidArgument("scale", "must be finite and positive, got " + std::to_string(scale));
  }
  return Status::Ok();
}

Status ObjectNotFound(const std::string& scene_id, const std::string& object_id) {
  return NotFound("object_id", "no object '" + object_id + "' in scene '" + scene_id + "'");
}

Status InsertMeshRow(sqlite3* db, const MeshRecord& mesh) {
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db, Sql("INSERT INTO meshes (", kMeshColumns,
                                                           ") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, "
                                                           "?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19)")));
  s.Bind(1, mesh.mesh_id).Bind(2, mesh.name).Bind(3, mesh.sha256);
  s.Bind(4, static_cast<int64_t>(mesh.vertex_count)).Bind(5, static_cast<int64_t>(mesh.triangle_count));
  for (int i = 0; i < 3; ++i) {
    s.Bind(6 + i, mesh.bounds_min[i]).Bind(9 + i, mesh.bounds_max[i]);
  }
  s.Bind(12, StoredCode(kLengthUnitCodes, mesh.source_unit)).Bind(13, mesh.source_scale).Bind(14, mesh.create_time_ms);
  BindMaterial(s, 15, mesh.material);
  return s.Run();
}

Status InsertObjectRow(sqlite3* db, const ObjectRecord& object) {
  ASSIGN_OR_RETURN(Statement insert, Statement::Prepare(db, Sql("INSERT INTO objects (", kObjectColumns,
                                                                ") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, "
                                                                "?10, ?11, ?12, ?13)")));
  insert.Bind(1, object.object_id).Bind(2, object.scene_id).Bind(3, object.mesh_id).Bind(4, object.label);
  insert.BindBlob(5, EncodePose(object.pose)).Bind(6, object.scale).Bind(7, int64_t{object.on_table});
  insert.Bind(8, int64_t{object.instance_id});
  BindMaterial(insert, 9, object.material);
  return insert.Run();
}

// Bumps the scene's revision and update time; NOT_FOUND when the scene does not exist.
StatusOr<uint64_t> BumpRevision(sqlite3* db, const std::string& scene_id) {
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db,
                                                   "UPDATE scenes SET revision = revision + 1, update_time_ms = ?1 "
                                                   "WHERE scene_id = ?2 RETURNING revision"));
  s.Bind(1, NowMs()).Bind(2, scene_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return SceneNotFound(scene_id);
  auto revision = static_cast<uint64_t>(s.Int(0));
  RETURN_IF_ERROR(s.Run());
  return revision;
}

StatusOr<ObjectRecord> LoadObject(sqlite3* db, const std::string& scene_id, const std::string& object_id) {
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db, Sql("SELECT ", kObjectColumns,
                                                           " FROM objects WHERE object_id = ?1 AND scene_id = ?2")));
  s.Bind(1, object_id).Bind(2, scene_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return ObjectNotFound(scene_id, object_id);
  return ReadObject(s);
}

// In one transaction: the scene's revision bumped, the object loaded and handed to `write`, which
// changes and stores it. Returns the changed object and the new revision.
StatusOr<std::pair<ObjectRecord, uint64_t>> EditObject(sqlite3* db, const std::string& scene_id,
                                                       const std::string& object_id,
                                                       const std::function<Status(ObjectRecord&)>& write) {
  ObjectRecord object;
  uint64_t revision = 0;
  RETURN_IF_ERROR(sqlite::InTransaction(db, true, [&]() -> Status {
    ASSIGN_OR_RETURN(revision, BumpRevision(db, scene_id));
    ASSIGN_OR_RETURN(object, LoadObject(db, scene_id, object_id));
    return write(object);
  }));
  return std::make_pair(std::move(object), revision);
}

Status LoadObjects(sqlite3* db, SceneRecord& scene) {
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db, Sql("SELECT ", kObjectColumns,
                                                           " FROM objects WHERE scene_id = ?1 ORDER BY instance_id")));
  s.Bind(1, scene.scene_id);
  for (;;) {
    ASSIGN_OR_RETURN(bool row, s.Step());
    if (!row) return Status::Ok();
    ASSIGN_OR_RETURN(ObjectRecord object, ReadObject(s));
    scene.objects.push_back(std::move(object));
  }
}

}  // namespace

Catalogue::Catalogue(std::shared_ptr<Database> database)
    : database_(std::move(database)), mutex_(database_->mutex()), db_(database_->handle()) {}

StatusOr<std::unique_ptr<Catalogue>> Catalogue::Open(const std::filesystem::path& db_path) {
  ASSIGN_OR_RETURN(std::shared_ptr<Database> database, Database::Open(db_path));
  return std::make_unique<Catalogue>(std::move(database));
}

StatusOr<MeshRecord> Catalogue::InsertMesh(MeshRecord mesh) {
  std::lock_guard lock(mutex_);
  mesh.mesh_id = NewId("msh_");
  mesh.create_time_ms = NowMs();
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status { return InsertMeshRow(db_, mesh); }));
  return mesh;
}

StatusOr<MeshRecord> Catalogue::GetMesh(const std::string& mesh_id) {
  std::lock_guard lock(mutex_);
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Sql("SELECT ", kMeshColumns, " FROM meshes WHERE mesh_id = ?1")));
  s.Bind(1, mesh_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return MeshNotFound(mesh_id);
  return ReadMesh(s);
}

StatusOr<std::vector<MeshRecord>> Catalogue::ListMeshes(const std::string& after_id, int limit) {
  RETURN_IF_ERROR(CheckLimit(limit));
  std::lock_guard lock(mutex_);
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Sql("SELECT ", kMeshColumns,
                                                            " FROM meshes WHERE mesh_id > ?1 ORDER BY mesh_id LIMIT ?2")));
  s.Bind(1, after_id).Bind(2, int64_t{std::min(limit, kMaxListLimit)});
  std::vector<MeshRecord> meshes;
  for (;;) {
    ASSIGN_OR_RETURN(bool row, s.Step());
    if (!row) return meshes;
    ASSIGN_OR_RETURN(MeshRecord mesh, ReadMesh(s));
    meshes.push_back(std::move(mesh));
  }
}

StatusOr<std::pair<std::string, bool>> Catalogue::DeleteMesh(const std::string& mesh_id) {
  std::lock_guard lock(mutex_);
  std::pair<std::string, bool> result;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement exists, Statement::Prepare(db_, "SELECT 1 FROM meshes WHERE mesh_id = ?1"));
    exists.Bind(1, mesh_id);
    ASSIGN_OR_RETURN(bool found, exists.Step());
    if (!found) return MeshNotFound(mesh_id);

    ASSIGN_OR_RETURN(Statement users, Statement::Prepare(db_, "SELECT count(*) FROM objects WHERE mesh_id = ?1"));
    users.Bind(1, mesh_id);
    ASSIGN_OR_RETURN(bool counted, users.Step());
    if (int64_t count = counted ? users.Int(0) : 0; count > 0) {
      return FailedPrecondition("mesh_id", "mesh '" + mesh_id + "' is used by " + std::to_string(count) +
                                (count == 1 ? " object" : " objects"));
    }

    ASSIGN_OR_RETURN(Statement del, Statement::Prepare(db_, "DELETE FROM meshes WHERE mesh_id = ?1 RETURNING sha256"));
    del.Bind(1, mesh_id);
    ASSIGN_OR_RETURN(bool deleted, del.Step());
    if (!deleted) return MeshNotFound(mesh_id);
    result.first = del.Text(0);
    RETURN_IF_ERROR(del.Run());

    ASSIGN_OR_RETURN(Statement shared, Statement::Prepare(db_, "SELECT count(*) FROM meshes WHERE sha256 = ?1"));
    shared.Bind(1, result.first);
    ASSIGN_OR_RETURN(bool row, shared.Step());
    result.second = !row || shared.Int(0) == 0;
    return Status::Ok();
  }));
  return result;
}

StatusOr<SceneRecord> Catalogue::CreateScene(const std::string& name) {
  std::lock_guard lock(mutex_);
  SceneRecord scene;
  scene.scene_id = NewId("scn_");
  scene.name = name;
  scene.revision = 1;
  scene.create_time_ms = scene.update_time_ms = NowMs();
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Sql("INSERT INTO scenes (", kSceneColumns,
                                                              ", next_instance_id) VALUES (?1, ?2, ?3, ?4, ?5, ?6, "
                                                              "?7, ?8, ?9, ?10, ?11, ?12, ?13, 1)")));
    const TableRecord& t = scene.table;
    s.Bind(1, scene.scene_id).Bind(2, scene.name).Bind(3, int64_t{1}).Bind(4, int64_t{t.enabled});
    for (int i = 0; i < 3; ++i) s.Bind(5 + i, t.centre[i]).Bind(8 + i, t.axis[i]);
    s.Bind(11, t.angle_deg).Bind(12, scene.create_time_ms).Bind(13, scene.update_time_ms);
    return s.Run();
  }));
  return scene;
}

StatusOr<SceneRecord> Catalogue::GetScene(const std::string& scene_id) {
  std::lock_guard lock(mutex_);
  SceneRecord scene;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, false, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement s,
                     Statement::Prepare(db_, Sql("SELECT ", kSceneColumns, " FROM scenes WHERE scene_id = ?1")));
    s.Bind(1, scene_id);
    ASSIGN_OR_RETURN(bool row, s.Step());
    if (!row) return SceneNotFound(scene_id);
    scene = ReadScene(s);
    return LoadObjects(db_, scene);
  }));
  return scene;
}

StatusOr<std::vector<SceneRecord>> Catalogue::ListScenes(const std::string& after_id, int limit) {
  RETURN_IF_ERROR(CheckLimit(limit));
  std::lock_guard lock(mutex_);
  std::vector<SceneRecord> scenes;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, false, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Sql("SELECT ", kSceneColumns,
                                                              " FROM scenes WHERE scene_id > ?1 ORDER BY scene_id "
                                                              "LIMIT ?2")));
    s.Bind(1, after_id).Bind(2, int64_t{std::min(limit, kMaxListLimit)});
    for (;;) {
      ASSIGN_OR_RETURN(bool row, s.Step());
      if (!row) break;
      scenes.push_back(ReadScene(s));
    }
    for (auto& scene : scenes) RETURN_IF_ERROR(LoadObjects(db_, scene));
    return Status::Ok();
  }));
  return scenes;
}

Status Catalogue::DeleteScene(const std::string& scene_id) {
  std::lock_guard lock(mutex_);
  return sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, "DELETE FROM scenes WHERE scene_id = ?1"));
    s.Bind(1, scene_id);
    RETURN_IF_ERROR(s.Run());
    if (sqlite3_changes(db_) == 0) return SceneNotFound(scene_id);
    return Status::Ok();
  });
}

StatusOr<std::pair<ObjectRecord, uint64_t>> Catalogue::AddObject(ObjectRecord object) {
  RETURN_IF_ERROR(CheckPose(object.pose));
  RETURN_IF_ERROR(CheckScale(object.scale));
  std::lock_guard lock(mutex_);
  object.object_id = NewId("obj_");
  uint64_t revision = 0;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement scene, Statement::Prepare(db_,
                                                         "UPDATE scenes SET revision = revision + 1, "
                                                         "next_instance_id = next_instance_id + 1, update_time_ms = ?1 "
                                                         "WHERE scene_id = ?2 RETURNING revision, next_instance_id - 1"));
    scene.Bind(1, NowMs()).Bind(2, object.scene_id);
    ASSIGN_OR_RETURN(bool found, scene.Step());
    if (!found) return SceneNotFound(object.scene_id);
    revision = static_cast<uint64_t>(scene.Int(0));
    object.instance_id = static_cast<uint32_t>(scene.Int(1));
    RETURN_IF_ERROR(scene.Run());

    RETURN_IF_ERROR(CheckPlacement(db_, object.mesh_id, object.pose, object.scale));
    return InsertObjectRow(db_, object);
  }));
  return std::make_pair(std::move(object), revision);
}

StatusOr<Catalogue::AddedObjects> Catalogue::AddObjects(const std::string& scene_id, std::vector<ObjectRecord> objects,
                                                        const MeshRecord* new_mesh) {
  for (const ObjectRecord& object : objects) {
    RETURN_IF_ERROR(CheckPose(object.pose));
    RETURN_IF_ERROR(CheckScale(object.scale));
  }
  std::lock_guard lock(mutex_);
  AddedObjects added;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement scene, Statement::Prepare(db_,
                                                         "UPDATE scenes SET revision = revision + 1, "
                                                         "next_instance_id = next_instance_id + ?1, update_time_ms = ?2 "
                                                         "WHERE scene_id = ?3 RETURNING revision, next_instance_id - ?1"));
    scene.Bind(1, static_cast<int64_t>(objects.size())).Bind(2, NowMs()).Bind(3, scene_id);
    ASSIGN_OR_RETURN(bool found, scene.Step());
    if (!found) return SceneNotFound(scene_id);
    added.revision = static_cast<uint64_t>(scene.Int(0));
    auto instance_id = static_cast<uint32_t>(scene.Int(1));
    RETURN_IF_ERROR(scene.Run());
    if (new_mesh) {
      MeshRecord mesh = *new_mesh;
      mesh.mesh_id = NewId("msh_");
      mesh.create_time_ms = NowMs();
      RETURN_IF_ERROR(InsertMeshRow(db_, mesh));
      added.new_mesh_id = mesh.mesh_id;
    }
    for (ObjectRecord& object : objects) {
      object.object_id = NewId("obj_");
      object.scene_id = scene_id;
      if (object.mesh_id.empty()) object.mesh_id = added.new_mesh_id;
      object.instance_id = instance_id++;
      RETURN_IF_ERROR(CheckPlacement(db_, object.mesh_id, object.pose, object.scale));
      RETURN_IF_ERROR(InsertObjectRow(db_, object));
    }
    return Status::Ok();
  }));
  added.objects = std::move(objects);
  return added;
}

StatusOr<std::pair<ObjectRecord, uint64_t>> Catalogue::MoveObject(const std::string& scene_id,
                                                                  const std::string& object_id,
                                                                  const Eigen::Matrix4d& pose,
                                                                  std::optional<double> scale) {
  RETURN_IF_ERROR(CheckPose(pose));
  if (scale) RETURN_IF_ERROR(CheckScale(*scale));
  std::lock_guard lock(mutex_);
  return EditObject(db_, scene_id, object_id, [&](ObjectRecord& object) -> Status {
    object.pose = pose;
    if (scale) object.scale = *scale;
    RETURN_IF_ERROR(CheckPlacement(db_, object.mesh_id, object.pose, object.scale));
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, "UPDATE objects SET pose = ?1, scale = ?2 WHERE object_id = ?3"));
    s.BindBlob(1, EncodePose(object.pose)).Bind(2, object.scale).Bind(3, object_id);
    return s.Run();
  });
}

StatusOr<std::pair<ObjectRecord, uint64_t>> Catalogue::SetObjectMaterial(
    const std::string& scene_id, const std::string& object_id, const std::optional<MaterialRecord>& material) {
  std::lock_guard lock(mutex_);
  return EditObject(db_, scene_id, object_id, [&](ObjectRecord& object) -> Status {
    object.material = material;
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Sql("UPDATE objects SET (", kMaterialColumns,
                                                              ") = (?1, ?2, ?3, ?4, ?5) WHERE object_id = ?6")));
    BindMaterial(s, 1, object.material);
    s.Bind(6, object_id);
    return s.Run();
  });
}

StatusOr<uint64_t> Catalogue::RemoveObject(const std::string& scene_id, const std::string& object_id) {
  std::lock_guard lock(mutex_);
  uint64_t revision = 0;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(revision, BumpRevision(db_, scene_id));
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, "DELETE FROM objects WHERE object_id = ?1 AND scene_id = ?2"));
    s.Bind(1, object_id).Bind(2, scene_id);
    RETURN_IF_ERROR(s.Run());
    if (sqlite3_changes(db_) == 0) return ObjectNotFound(scene_id, object_id);
    return Status::Ok();
  }));
  return revision;
}

StatusOr<uint64_t> Catalogue::SetTable(const std::string& scene_id, const TableRecord& table) {
  RETURN_IF_ERROR(CheckTable(table));
  std::lock_guard lock(mutex_);
  uint64_t revision = 0;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(revision, BumpRevision(db_, scene_id));
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_,
                                                     "UPDATE scenes SET table_enabled = ?1, table_centre_x = ?2, "
                                                     "table_centre_y = ?3, table_centre_z = ?4, table_axis_x = ?5, "
                                                     "table_axis_y = ?6, table_axis_z = ?7, table_angle_deg = ?8 "
                                                     "WHERE scene_id = ?9"));
    s.Bind(1, int64_t{table.enabled});
    for (int i = 0; i < 3; ++i) s.Bind(2 + i, table.centre[i]).Bind(5 + i, table.axis[i]);
    s.Bind(8, table.angle_deg).Bind(9, scene_id);
    return s.Run();
  }));
  return revision;
}

}  // namespace vscan::store
