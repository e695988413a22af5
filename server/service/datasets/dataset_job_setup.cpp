#include "service/datasets/dataset_job_setup.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <tuple>

#include "geometry/mesh_import.h"
#include "geometry/open_bin_mesh.h"
#include "physics/fill_checks.h"
#include "physics/part_geometry.h"
#include "sensor/presets.h"
#include "vscan/plan/bin_fill_plan.h"

namespace vscan::service {
namespace {

using dataset::DatasetPart;

// Parts of different bins are one type when they are the same mesh at the same size.
using PartKey = std::tuple<std::string, std::string, std::string, double>;

PartKey KeyOf(const DatasetPart& part) { return {part.mesh_file, part.mesh_id, part.unit, part.scale}; }

StatusOr<TriangleMesh> ScaledMesh(const DatasetPart& part, const DatasetMeshLoader& load, const std::string& field) {
  ASSIGN_OR_RETURN(TriangleMesh mesh, load(part, field));
  return physics::ScalePart(std::move(mesh), part.scale, field);
}

// A preset by name or the four values, each within [0, 1] and roughness above 0, as the server
// checks an object's (the plan's reader checked both; a plan built in code has not).
StatusOr<sensor::Material> ResolveMaterial(const plan::MaterialPlan& asked, const std::string& field) {
  if (!asked.preset.empty()) {
    const sensor::MaterialPreset* preset = sensor::FindMaterialPreset(asked.preset);
    if (!preset) return InvalidArgument(field, "unknown preset '" + asked.preset + "' (vscan materials lists them)");
    return preset->material;
  }
  const sensor::Material material{asked.diffuse_albedo, asked.metallic, asked.roughness, asked.specular_reflectance};
  RETURN_IF_ERROR(sensor::ValidateMaterial(material, field));
  if (!(material.roughness > 0)) return InvalidArgument(field + ".roughness", "must be within (0, 1]");
  return material;
}

StatusOr<DatasetBinSetup> PrepareBin(const dataset::DatasetBinFill& fill, const std::string& field,
                                     const DatasetMeshLoader& load, std::map<PartKey, uint32_t>& obj_ids,
                                     std::vector<dataset::PartModel>& models) {
  DatasetBinSetup bin;
  bin.spec.inner_size = fill.inner_size_m;
  bin.spec.wall_thickness = fill.wall_thickness_m;
  bin.options.max_simulated_s = fill.max_simulated_s;
  for (size_t i = 0; i < fill.parts.size(); ++i) {
    const DatasetPart& asked = fill.parts[i];
    const std::string part_field = field + ".parts[" + std::to_string(i) + "]";
    physics::PartType part;
    ASSIGN_OR_RETURN(part.mesh, ScaledMesh(asked, load, part_field));
    part.name = asked.name;
    part.count = asked.count;
    part.mass_kg = asked.mass_kg;
    part.density_kg_per_m3 = asked.density_kg_per_m3;
    part.collision = asked.collision == "convex_decomposition" ? physics::PartCollision::kConvexDecomposition
                                                               : physics::PartCollision::kConvexHull;
    const auto [found, added] = obj_ids.emplace(KeyOf(asked), static_cast<uint32_t>(models.size() + 1));
    if (added) {
      dataset::PartModel model;
      model.obj_id = found->second;
      model.mesh = part.mesh;
      models.push_back(std::move(model));
    }
    bin.obj_ids.push_back(found->second);
    bin.parts.push_back(std::move(part));
    std::vector<sensor::Material> materials;
    for (size_t k = 0; k < asked.materials.size(); ++k) {
      const std::string choice = asked.materials.size() > 1 ? ".choose[" + std::to_string(k) + "]" : "";
      ASSIGN_OR_RETURN(sensor::Material material,
                       ResolveMaterial(asked.materials[k], part_field + ".material" + choice));
      materials.push_back(material);
    }
    bin.material_plans.push_back(asked.materials);
    bin.materials.push_back(std::move(materials));
  }
  // The fill's own checks, in the words a bin fill's plan gets (parts[i].mass_kg and the rest); the
  // masses from hulls, since a decomposition is the fill's to make.
  Status checked = physics::CheckFillInput(bin.spec, bin.parts, bin.options);
  if (checked.ok()) {
    std::vector<physics::PartType> hulls = bin.parts;
    for (physics::PartType& part : hulls) part.collision = physics::PartCollision::kConvexHull;
    checked = physics::CheckPartMasses(physics::MakePartGeometries(hulls, bin.options.hull_tolerance_m));
  }
  if (!checked.ok()) return checked.WithFieldPrefix(field);
  bin.bin_mesh =
      std::make_shared<const TriangleMesh>(geometry::OpenBinMesh(bin.spec.inner_size, bin.spec.wall_thickness));
  return bin;
}

// The preset's camera resampled to width x height over the same field of view.
sensor::PinholeCamera Resampled(const sensor::PinholeCamera& camera, uint32_t width, uint32_t height) {
  if (width == 0) return camera;
  sensor::PinholeCamera out = camera;
  const double sx = double(width) / camera.width, sy = double(height) / camera.height;
  out.width = width;
  out.height = height;
  out.fx *= sx;
  out.cx *= sx;
  out.fy *= sy;
  out.cy *= sy;
  return out;
}

StatusOr<DatasetSensorSetup> PrepareSensor(const dataset::DatasetSensor& asked, const std::string& field,
                                           uint64_t max_rays) {
  const sensor::SensorPreset* preset = sensor::FindSensorPreset(asked.preset);
  if (!preset) return NotFound(field + ".preset", "no preset '" + asked.preset + "' (vscan sensors lists them)");
  DatasetSensorSetup setup;
  setup.camera = Resampled(preset->camera, asked.width, asked.height);
  RETURN_IF_ERROR(sensor::ValidateCamera(setup.camera, field, max_rays));
  setup.measurement.noise = preset->noise;
  setup.measurement.structured_light = preset->structured_light;
  if (setup.measurement.structured_light) setup.measurement.structured_light->camera = setup.camera;
  setup.modulation_frequency_hz = preset->modulation_frequency_hz;
  setup.illumination = preset->illumination;
  return setup;
}

// Every view's distance to the bin's floor lies within the depths the sensor measures.
Status CheckWorkingRange(const dataset::DatasetPlan& plan, const sensor::PinholeCamera& camera, size_t sensor_index) {
  const auto [nearest_m, farthest_m] = dataset::ViewDistanceRange(plan);
  if (nearest_m >= camera.near && farthest_m <= camera.far) return Status::Ok();
  const bool ranged = plan.views.max_distance_m > 0;
  char text[240];
  std::snprintf(text, sizeof(text), "[%g, %g] m to the bin's floor leaves the working range [%g, %g] m of sensors[%zu] ('%s')",
                nearest_m, farthest_m, camera.near, camera.far, sensor_index, plan.sensors[sensor_index].c_str());
  return InvalidArgument(ranged ? "views.distance_m" : "camera_height_m", text);
}

}  // namespace

DatasetMeshLoader MeshFilesFrom(std::filesystem::path plan_dir) {
  return [plan_dir = std::move(plan_dir)](const DatasetPart& part,
                                          const std::string& field) -> StatusOr<TriangleMesh> {
    if (part.mesh_file.empty()) {
      return InvalidArgument(field + ".mesh_id", "stored meshes exist only on a server; name a mesh file");
    }
    const std::filesystem::path path = std::filesystem::path(part.mesh_file).is_absolute()
                                           ? std::filesystem::path(part.mesh_file)
                                           : plan_dir / part.mesh_file;
    std::ifstream in(path, std::ios::binary);
    if (!in) return NotFound(field + ".mesh", "cannot read " + path.string());
    std::ostringstream bytes;
    bytes << in.rdbuf();
    const StatusOr<TriangleMesh> mesh =
        geometry::ImportMesh(bytes.str(), geometry::MeshFileFormat::kAuto, *plan::MetresPerUnit(part.unit));
    if (!mesh.ok()) return InvalidArgument(field + ".mesh", path.string() + ": " + mesh.status().message());
    return mesh;
  };
}

StatusOr<DatasetSetup> PrepareDataset(const dataset::DatasetPlan& plan, const DatasetMeshLoader& load,
                                      uint64_t max_rays_per_scan, const DatasetLightResolver& resolve_light) {
  RETURN_IF_ERROR(dataset::CheckPlan(plan));
  if (plan.bin_fills.empty()) return InvalidArgument("bins", "each bin needs its box and parts (name, box, parts)");
  DatasetSetup setup;
  setup.plan = plan;
  std::map<PartKey, uint32_t> obj_ids;
  for (size_t b = 0; b < plan.bin_fills.size(); ++b) {
    ASSIGN_OR_RETURN(DatasetBinSetup bin,
                     PrepareBin(plan.bin_fills[b], "bins[" + std::to_string(b) + "]", load, obj_ids, setup.parts));
    setup.bins.push_back(std::move(bin));
  }
  for (size_t s = 0; s < plan.sensors.size(); ++s) {
    const dataset::DatasetSensor asked =
        plan.sensor_setups.empty() ? dataset::DatasetSensor{plan.sensors[s], 0, 0} : plan.sensor_setups[s];
    ASSIGN_OR_RETURN(DatasetSensorSetup sensor,
                     PrepareSensor(asked, "sensors[" + std::to_string(s) + "]", max_rays_per_scan));
    if (plan.returned_light) {
      if (!resolve_light) {
        return FailedPrecondition("returned_light", "lighting a dataset needs the server's dataset job");
      }
      ASSIGN_OR_RETURN(sensor.measurement.returned_light, resolve_light(*plan.returned_light, sensor));
    }
    setup.sensors.push_back(std::move(sensor));
    RETURN_IF_ERROR(CheckWorkingRange(plan, setup.sensors.back().camera, s));
  }
  return setup;
}

Status AddDatasetPicks(DatasetSetup& setup, std::shared_ptr<const robot::KinematicChain> robot_chain) {
  if (!setup.plan.picks) return Status::Ok();
  std::vector<uint64_t> parts_per_bin;
  for (const DatasetBinSetup& bin : setup.bins) {
    uint64_t count = 0;
    for (const physics::PartType& part : bin.parts) count += part.count;
    parts_per_bin.push_back(count);
  }
  ASSIGN_OR_RETURN(setup.picks,
                   PrepareDatasetPicks(*setup.plan.picks, std::move(robot_chain), setup.parts, parts_per_bin));
  return Status::Ok();
}

}  // namespace vscan::service
