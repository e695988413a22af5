#pragma once
// A dataset plan in engine terms: each bin's box and part types (meshes loaded, in metres, scaled),
// the fill options, each sensor's camera and measurement model, and the part models for
// models_info.json. Part types are numbered (obj_id) across the plan by their first appearance.

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "capture/measurement_spec.h"
#include "physics/bin_fill.h"
#include "capture/returned_light.h"
#include "sensor/camera.h"
#include "sensor/material.h"
#include "sensor/presets.h"
#include "service/datasets/format/dataset_frame.h"
#include "service/datasets/format/dataset_plan.h"
#include "service/datasets/dataset_picks.h"
#include "vscan/common/status.h"

namespace vscan::service {

struct DatasetBinSetup {
  physics::BinSpec spec;
  std::vector<physics::PartType> parts;  // scaled, in metres
  std::vector<uint32_t> obj_ids;         // obj_ids[i]: the plan-wide part type of parts[i]
  // materials[i]: what parts[i] may be made of, as the plan names them and in engine terms (empty:
  // the default); a scene takes one of them (dataset::PartMaterialIndex).
  std::vector<std::vector<plan::MaterialPlan>> material_plans;
  std::vector<std::vector<sensor::Material>> materials;
  physics::FillOptions options;          // seed set per scene
  std::shared_ptr<const TriangleMesh> bin_mesh;
};

struct DatasetSensorSetup {
  sensor::PinholeCamera camera;
  capture::MeasurementSpec measurement;  // seed set per scene
  double modulation_frequency_hz = 0;    // the preset's, for time of flight
  sensor::PresetIllumination illumination;
};

struct DatasetSetup {
  dataset::DatasetPlan plan;
  std::vector<DatasetBinSetup> bins;
  std::vector<DatasetSensorSetup> sensors;
  std::vector<dataset::PartModel> parts;  // parts[k].obj_id == k + 1
  // Set when the plan checks picks and its robot is resolved (AddDatasetPicks).
  std::shared_ptr<const DatasetPickSetup> picks;
};

// The mesh of a part as its file or the store holds it, in metres and unscaled. field names the
// part in errors, e.g. "bins[0].parts[1]".
using DatasetMeshLoader =
    std::function<StatusOr<TriangleMesh>(const dataset::DatasetPart& part, const std::string& field)>;

// Parts' mesh files read from disk, relative paths from plan_dir; stored mesh ids are refused.
DatasetMeshLoader MeshFilesFrom(std::filesystem::path plan_dir);

// The plan's returned_light for one sensor in engine terms, checked as a scan's returned_light is
// (the server's ReturnedLight rules); INVALID_ARGUMENT naming "returned_light.<key>".
using DatasetLightResolver = std::function<StatusOr<capture::ReturnedLightSpec>(
    const plan::ReturnedLightPlan& light, const DatasetSensorSetup& sensor)>;

// InvalidArgument (naming the field) when the plan does not describe its bins, names an unknown
// preset, or a part is too small or large once scaled; errors of load pass through. A plan with
// returned_light needs resolve_light (FAILED_PRECONDITION without).
StatusOr<DatasetSetup> PrepareDataset(const dataset::DatasetPlan& plan, const DatasetMeshLoader& load,
                                      uint64_t max_rays_per_scan, const DatasetLightResolver& resolve_light = {});

// The plan's picks with robot_chain, the robot the plan names: PrepareDatasetPicks' errors.
Status AddDatasetPicks(DatasetSetup& setup, std::shared_ptr<const robot::KinematicChain> robot_chain);

}  // namespace vscan::service
