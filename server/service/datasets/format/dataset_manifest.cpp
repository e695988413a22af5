#include "service/datasets/format/dataset_manifest.h"

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/dataset_materials.h"
#include "service/datasets/format/durable_file.h"
#include "service/job/json_writer.h"

#include <variant>

namespace vscan::service::dataset {
namespace {

void Names(JsonWriter& json, const std::vector<std::string>& names) {
  json.Open('[');
  for (const std::string& name : names) json.Value(name);
  json.Close(']');
}

// What each bin is filled with and how each sensor scans, when the plan says: two plans that name
// the same bins but fill them differently are two datasets.
void Fills(JsonWriter& json, const DatasetPlan& plan) {
  json.Key("bin_fills").Open('[');
  for (const DatasetBinFill& fill : plan.bin_fills) {
    json.Open('{');
    json.Key("inner_size_m").Open('[');
    for (int axis = 0; axis < 3; ++axis) json.Value(fill.inner_size_m[axis]);
    json.Close(']');
    json.Key("wall_m").Value(fill.wall_thickness_m);
    json.Key("max_simulated_s").Value(fill.max_simulated_s);
    json.Key("parts").Open('[');
    for (const DatasetPart& part : fill.parts) {
      json.Open('{');
      json.Key("mesh").Value(part.mesh_file);
      json.Key("mesh_id").Value(part.mesh_id);
      json.Key("unit").Value(part.unit);
      json.Key("scale").Value(part.scale);
      json.Key("count").Value(uint64_t{part.count});
      json.Key("name").Value(part.name);
      // Only where a plan sets them, so that a dataset written before parts had them keeps its identity.
      if (part.mass_kg) json.Key("mass_kg").Value(*part.mass_kg);
      if (part.density_kg_per_m3 != DatasetPart{}.density_kg_per_m3) {
        json.Key("density_kg_per_m3").Value(part.density_kg_per_m3);
      }
      if (part.collision != DatasetPart{}.collision) json.Key("collision").Value(part.collision);
      if (!part.materials.empty()) {
        json.Key("materials").Open('[');
        for (const plan::MaterialPlan& material : part.materials) WriteMaterial(json, material);
        json.Close(']');
      }
      json.Close('}');
    }
    json.Close(']').Close('}');
  }
  json.Close(']');
  json.Key("sensor_setups").Open('[');
  for (const DatasetSensor& sensor : plan.sensor_setups) {
    json.Open('{');
    json.Key("preset").Value(sensor.preset);
    json.Key("width").Value(uint64_t{sensor.width});
    json.Key("height").Value(uint64_t{sensor.height});
    json.Close('}');
  }
  json.Close(']');
  json.Key("camera_height_m").Value(plan.camera_height_m);
  json.Key("fail_on_underfilled_bin").Value(plan.fail_on_underfilled_bin);
}

// Only a plan that asks for other views than the single one straight down names them, so that a
// dataset written before views existed resumes under the same manifest.
void Views(JsonWriter& json, const DatasetPlan& plan) {
  const auto [nearest_m, farthest_m] = ViewDistanceRange(plan);
  json.Key("views").Open('{');
  json.Key("count").Value(uint64_t{plan.views.count});
  json.Key("cone_deg").Value(plan.views.cone_deg);
  json.Key("distance_m").Open('[').Value(nearest_m).Value(farthest_m).Close(']');
  json.Close('}');
}

// Only a plan that lights its scans names the light (every key, 0 where the default holds).
void ReturnedLight(JsonWriter& json, const plan::ReturnedLightPlan& light) {
  const double values[] = {light.emitter_w_per_sr, light.emitter_half_angle_deg, light.exposure_s,
                           light.aperture_diameter_m, light.quantum_efficiency, light.wavelength_m,
                           light.full_well_e, light.read_noise_e, light.min_snr, light.reference_e,
                           light.indirect_samples, light.indirect_stride_px, light.modulation_frequency_hz,
                           light.interreflection_ratio, light.ambient_irradiance_w_per_m2};
  static_assert(std::size(values) == std::size(plan::kReturnedLightKeys));
  json.Key("returned_light").Open('{');
  for (size_t i = 0; i < std::size(values); ++i) json.Key(plan::kReturnedLightKeys[i]).Value(values[i]);
  json.Close('}');
}

void PoseValues(JsonWriter& json, const char* key, const Pose3& pose) {
  json.Key(key).Open('{');
  json.Key("R").Open('[');
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) json.Value(pose.linear()(r, c));
  }
  json.Close(']');
  json.Key("t_m").Open('[');
  for (int axis = 0; axis < 3; ++axis) json.Value(pose.translation()[axis]);
  json.Close(']').Close('}');
}

// Only a plan that checks picks names them: the robot, where it stands, the gripper and every option.
void Picks(JsonWriter& json, const DatasetPicks& picks) {
  json.Key("picks").Open('{');
  json.Key("robot_id").Value(picks.robot_id);
  PoseValues(json, "world_from_base", picks.world_from_base);
  if (picks.flange_from_tool) PoseValues(json, "flange_from_tool", *picks.flange_from_tool);
  json.Key("gripper").Open('{');
  json.Key("kind").Value(GripperKind(picks.gripper));
  if (const auto* cup = std::get_if<grasping::SuctionCup>(&picks.gripper)) {
    json.Key("diameter_m").Value(cup->diameter_m).Key("stroke_m").Value(cup->stroke_m);
    json.Key("max_tilt_deg").Value(cup->max_tilt_deg).Key("min_flat_fraction").Value(cup->min_flat_fraction);
  } else {
    const auto& jaws = std::get<grasping::ParallelJaws>(picks.gripper);
    json.Key("min_opening_m").Value(jaws.min_opening_m).Key("max_opening_m").Value(jaws.max_opening_m);
    json.Key("finger_width_m").Value(jaws.finger_width_m).Key("finger_depth_m").Value(jaws.finger_depth_m);
    json.Key("max_friction_angle_deg").Value(jaws.max_friction_angle_deg);
    json.Key("finger_length_m").Value(jaws.finger_length_m).Key("finger_thickness_m").Value(jaws.finger_thickness_m);
  }
  json.Close('}');
  const grasping::GraspOptions& grasp = picks.grasp_options;
  json.Key("grasp_options").Open('{');
  json.Key("max_grasps").Value(uint64_t{grasp.max_grasps}).Key("seed").Value(grasp.seed);
  json.Key("candidates").Value(uint64_t{grasp.candidates}).Key("surface_samples").Value(uint64_t{grasp.surface_samples});
  json.Close('}');
  const grasping::PickOptions& pick = picks.pick_options;
  json.Key("pick_options").Open('{');
  json.Key("approach_distance_m").Value(pick.sweep.approach_m);
  json.Key("max_approach_tilt_deg").Value(pick.max_approach_tilt_deg);
  json.Key("cover_distance_m").Value(pick.cover_distance_m);
  json.Key("max_reach_checks").Value(uint64_t{pick.max_reach_checks});
  json.Key("body_length_m").Value(pick.sweep.body_length_m);
  json.Key("ik_iterations").Value(uint64_t{picks.ik_iterations});
  json.Close('}').Close('}');
}

}  // namespace

std::string DatasetManifestJson(const DatasetPlan& plan) {
  JsonWriter json;
  json.Open('{');
  json.Key("format").Value("vscan-dataset");
  json.Key("layout_version").Value(kLayoutVersion);
  json.Key("scene_order").Value("seed, bin, sensor");
  json.Key("scene_count").Value(SceneCount(plan));
  json.Key("plan").Open('{');
  json.Key("name").Value(plan.name);
  json.Key("bins");
  Names(json, plan.bins);
  json.Key("seeds").Open('[');
  for (const uint64_t seed : plan.seeds) json.Value(seed);
  json.Close(']');
  json.Key("sensors");
  Names(json, plan.sensors);
  json.Key("depth_scale_mm").Value(plan.depth_scale_mm);
  if (!plan.bin_fills.empty()) Fills(json, plan);
  if (plan.views != DatasetViews{}) Views(json, plan);
  if (plan.returned_light) ReturnedLight(json, *plan.returned_light);
  if (plan.picks) Picks(json, *plan.picks);
  json.Close('}').Close('}');
  return json.str() + "\n";
}

std::string SceneIndexJson(const DatasetPlan& plan, const std::vector<uint32_t>& record_crc32) {
  JsonWriter json;
  json.Open('{');
  json.Key("layout_version").Value(kLayoutVersion);
  json.Key("scene_count").Value(SceneCount(plan));
  json.Key("scenes").Open('[');
  for (uint64_t id = 0; id < SceneCount(plan); ++id) {
    const SceneKey key = SceneAt(plan, id);
    json.Open('{');
    json.Key("scene_id").Value(id);
    json.Key("seed").Value(key.seed);
    json.Key("bin").Value(plan.bins[key.bin_index]);
    json.Key("sensor").Value(plan.sensors[key.sensor_index]);
    json.Key("record_crc32").Value(uint64_t{record_crc32[id]});
    json.Close('}');
  }
  json.Close(']').Close('}');
  return json.str() + "\n";
}

Status EnsureRootFile(const std::filesystem::path& root, const std::string& relative, const std::string& bytes,
                      const std::string& writer) {
  const std::filesystem::path path = root / relative;
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    ASSIGN_OR_RETURN(const std::string present, ReadWholeFile(path));
    if (present != bytes) {
      return FailedPrecondition(path.string() + " differs from this plan's: the directory holds another dataset");
    }
    return Status::Ok();
  }
  std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) return Internal("cannot create " + path.parent_path().string() + ": " + ec.message());
  return ReplaceFileDurably(path, bytes, ".tmp-" + writer);
}

}  // namespace vscan::service::dataset
