#include "service/localization/localization_run.h"

#include <chrono>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "service/clouds/cloud_store.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {
namespace {

StatusOr<std::shared_ptr<const TriangleMesh>> ScaledPart(scenes::SceneRegistry& registry,
                                                         const LocalizePartPlan& part) {
  auto mesh = registry.LoadMesh(part.mesh_id);
  if (!mesh.ok()) {
    if (mesh.status().code() == StatusCode::kNotFound) {
      return NotFound(part.field + ": no mesh '" + part.mesh_id + "'");
    }
    return mesh.status();
  }
  if (part.scale == 1) return *mesh;
  auto scaled = std::make_shared<TriangleMesh>(**mesh);
  for (Eigen::Vector3f& v : scaled->vertices) v *= static_cast<float>(part.scale);
  return std::shared_ptr<const TriangleMesh>(std::move(scaled));
}

struct SearchedCloud {
  PointCloud cloud;
  store::CloudFrame frame = store::CloudFrame::kWorld;
  std::optional<Eigen::Vector3d> sensor_position;  // in the cloud's frame
};

StatusOr<SearchedCloud> ReadStoredCloud(const StoredClouds& clouds, const std::string& cloud_id) {
  ASSIGN_OR_RETURN(const StoredCloud stored, LoadCloud(clouds, cloud_id));
  SearchedCloud searched;
  ASSIGN_OR_RETURN(searched.cloud, ParsePly(stored.ply, "cloud '" + cloud_id + "'",
                                            std::numeric_limits<uint64_t>::max()));
  searched.frame = stored.record.frame;
  if (searched.frame == store::CloudFrame::kSensor) {
    searched.sensor_position = Eigen::Vector3d::Zero();
  } else if (stored.record.world_from_sensor) {
    searched.sensor_position = stored.record.world_from_sensor->block<3, 1>(0, 3);
  }
  return searched;
}

// The normals the localizer gets: empty means "estimate them".
StatusOr<std::span<const Eigen::Vector3f>> ChooseNormals(const PointCloud& cloud, NormalSource source) {
  switch (source) {
    case NormalSource::kEstimate:
      return std::span<const Eigen::Vector3f>();
    case NormalSource::kCloud:
      if (cloud.normals.size() != cloud.positions.size()) {
        return FailedPrecondition("options.normal_source", "the cloud has no normals (POINT_FIELD_NORMAL)");
      }
      return std::span<const Eigen::Vector3f>(cloud.normals);
    case NormalSource::kAuto:
      break;
  }
  if (cloud.estimated_normals.size() == cloud.positions.size()) {
    return std::span<const Eigen::Vector3f>(cloud.estimated_normals);
  }
  return std::span<const Eigen::Vector3f>();
}

}  // namespace

StatusOr<LocalizeOutcome> RunLocalize(scenes::SceneRegistry& registry, const StoredClouds& clouds,
                                      const LocalizePlan& plan, const std::atomic<bool>* cancel,
                                      const localization::LocalizeProgressCallback& progress,
                                      localization::PartModelCache* models) {
  const auto start = std::chrono::steady_clock::now();
  if (plan.parts.empty()) return InvalidArgument("parts", "required (at least one part)");
  if (progress) progress({0, 0, "reading the parts and the cloud"});
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;
  std::vector<localization::PartQuery> queries;
  const localization::PartModelSettings settings = localization::ModelSettingsOf(plan.options);
  for (const LocalizePartPlan& part : plan.parts) {
    ASSIGN_OR_RETURN(auto mesh, ScaledPart(registry, part));
    meshes.push_back(std::move(mesh));
    queries.push_back({meshes.back().get(), part.max_instances, nullptr});
    if (models == nullptr) continue;
    const TriangleMesh& scaled = *meshes.back();
    ASSIGN_OR_RETURN(queries.back().model,
                     models->Get(localization::PartModelKey(part.mesh_id, part.scale, settings),
                                 [&] { return localization::BuildPartModel(scaled, part.field, settings); }));
  }
  SearchedCloud searched;
  if (!plan.cloud_id.empty()) {
    ASSIGN_OR_RETURN(searched, ReadStoredCloud(clouds, plan.cloud_id));
  } else {
    searched.cloud.positions = plan.points;
    if (!plan.normals.empty()) searched.cloud.normals = plan.normals;
  }
  ASSIGN_OR_RETURN(const auto normals, ChooseNormals(searched.cloud, plan.normal_source));
  localization::LocalizerOptions options = plan.options;
  options.viewpoint = plan.viewpoint.value_or(searched.sensor_position.value_or(Eigen::Vector3d::Zero()));
  if (plan.viewpoint || searched.sensor_position) options.sensor_position = options.viewpoint;

  LocalizeOutcome outcome;
  ASSIGN_OR_RETURN(outcome.result, localization::LocalizeParts(queries, searched.cloud.positions, normals, options,
                                                                cancel, progress));
  outcome.frame = searched.frame;
  outcome.points = searched.cloud.positions.size();
  outcome.localize_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

}  // namespace vscan::service
