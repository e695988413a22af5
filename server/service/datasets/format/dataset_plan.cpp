#include "service/datasets/format/dataset_plan.h"

#include <cmath>
#include <cstdio>
#include <set>

namespace vscan::service::dataset {
namespace {

Status CheckNames(const std::vector<std::string>& names, const std::string& field) {
  if (names.empty()) return InvalidArgument(field, "lists nothing");
  std::set<std::string> seen;
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string path = field + "[" + std::to_string(i) + "]";
    const std::string& name = names[i];
    if (name.empty()) return InvalidArgument(path, "is empty");
    for (const char c : name) {
      if (c < 0x21 || c > 0x7e || c == '/' || c == '"' || c == '\\') {
        return InvalidArgument(path, "'" + name + "' holds a character other than printable ASCII without / \" \\");
      }
    }
    if (!seen.insert(name).second) return InvalidArgument(path, "'" + name + "' appears twice");
  }
  return Status::Ok();
}

Status CheckViews(const DatasetViews& views) {
  if (views.count < 1 || views.count > kMaxViewsPerScene) {
    return InvalidArgument("views.count", "must be within [1, " + std::to_string(kMaxViewsPerScene) + "]");
  }
  if (!std::isfinite(views.cone_deg) || views.cone_deg < 0 || views.cone_deg > kMaxViewConeDeg) {
    return InvalidArgument("views.cone_deg", "must be within [0, 80] degrees of straight down");
  }
  if (views.min_distance_m == 0 && views.max_distance_m == 0) return Status::Ok();
  const bool finite = std::isfinite(views.min_distance_m) && std::isfinite(views.max_distance_m);
  if (!finite || views.min_distance_m <= 0 || views.max_distance_m > 100 || views.min_distance_m > views.max_distance_m) {
    return InvalidArgument("views.distance_m", "must be [min, max] with 0 < min <= max <= 100 m");
  }
  return Status::Ok();
}

}  // namespace

std::pair<double, double> ViewDistanceRange(const DatasetPlan& plan) {
  if (plan.views.min_distance_m == 0 && plan.views.max_distance_m == 0) {
    return {plan.camera_height_m, plan.camera_height_m};
  }
  return {plan.views.min_distance_m, plan.views.max_distance_m};
}

std::vector<uint64_t> SeedRange(uint64_t first, uint64_t count) {
  std::vector<uint64_t> seeds(count);
  for (uint64_t i = 0; i < count; ++i) seeds[i] = first + i;
  return seeds;
}

Status CheckPlan(const DatasetPlan& plan) {
  RETURN_IF_ERROR(CheckNames(plan.bins, "bins"));
  RETURN_IF_ERROR(CheckNames(plan.sensors, "sensors"));
  if (plan.seeds.empty()) return InvalidArgument("seeds", "lists nothing");
  std::set<uint64_t> seen;
  for (size_t i = 0; i < plan.seeds.size(); ++i) {
    if (!seen.insert(plan.seeds[i]).second) {
      return InvalidArgument("seeds[" + std::to_string(i) + "]", std::to_string(plan.seeds[i]) + " appears twice");
    }
  }
  if (!std::isfinite(plan.depth_scale_mm) || plan.depth_scale_mm <= 0) {
    return InvalidArgument("depth_scale_mm", "must be a positive number of millimetres");
  }
  if (!plan.bin_fills.empty()) {
    if (plan.bin_fills.size() != plan.bins.size()) return InvalidArgument("bins", "describe every bin's fill or none");
    for (size_t i = 0; i < plan.bin_fills.size(); ++i) {
      RETURN_IF_ERROR(CheckBinFill(plan.bin_fills[i], "bins[" + std::to_string(i) + "]"));
    }
  }
  if (!plan.sensor_setups.empty()) {
    if (plan.sensor_setups.size() != plan.sensors.size()) return InvalidArgument("sensors", "one setup per sensor");
    for (size_t i = 0; i < plan.sensor_setups.size(); ++i) {
      RETURN_IF_ERROR(CheckSensor(plan.sensor_setups[i], "sensors[" + std::to_string(i) + "]"));
    }
  }
  if (!std::isfinite(plan.camera_height_m) || plan.camera_height_m <= 0 || plan.camera_height_m > 100) {
    return InvalidArgument("camera_height_m", "must be within (0, 100] m");
  }
  RETURN_IF_ERROR(CheckViews(plan.views));
  // The floor's centre is the deepest point on the optical axis a depth image must hold.
  const double farthest_m = ViewDistanceRange(plan).second;
  if (farthest_m * 1000.0 / plan.depth_scale_mm > 65535.0) {
    char text[200];
    std::snprintf(text, sizeof(text), "the floor %g m from the camera (%s) does not fit %s of %g mm", farthest_m,
                  plan.views.max_distance_m > 0 ? "views.distance_m" : "camera_height_m", "16-bit depth units",
                  plan.depth_scale_mm);
    return InvalidArgument("depth_scale_mm", text);
  }
  const double scenes = double(plan.seeds.size()) * double(plan.bins.size()) * double(plan.sensors.size());
  if (scenes * plan.views.count > double(kMaxScenes)) {
    return InvalidArgument("seeds", "seeds x bins x sensors x views must be at most " + std::to_string(kMaxScenes) +
                                        " images, the plan makes " + std::to_string(uint64_t(scenes * plan.views.count)));
  }
  return Status::Ok();
}

Status CheckShard(uint32_t shard_index, uint32_t shard_count) {
  if (shard_count == 0) return InvalidArgument("shard_count", "must be at least 1");
  if (shard_index >= shard_count) {
    return InvalidArgument("shard_index", std::to_string(shard_index) + " is not below the shard count " +
                                              std::to_string(shard_count));
  }
  return Status::Ok();
}

uint64_t SceneCount(const DatasetPlan& plan) {
  return uint64_t{plan.seeds.size()} * plan.bins.size() * plan.sensors.size();
}

SceneKey SceneAt(const DatasetPlan& plan, uint64_t scene_id) {
  SceneKey key;
  key.scene_id = scene_id;
  key.sensor_index = scene_id % plan.sensors.size();
  const uint64_t seed_and_bin = scene_id / plan.sensors.size();
  key.bin_index = seed_and_bin % plan.bins.size();
  key.seed_index = seed_and_bin / plan.bins.size();
  key.seed = plan.seeds[key.seed_index];
  return key;
}

uint32_t ShardOfScene(const DatasetPlan& plan, uint64_t scene_id, uint32_t shard_count) {
  return static_cast<uint32_t>(SceneAt(plan, scene_id).seed_index % shard_count);
}

std::vector<uint64_t> ScenesOfShard(const DatasetPlan& plan, uint32_t shard_index, uint32_t shard_count) {
  const uint64_t per_seed = uint64_t{plan.bins.size()} * plan.sensors.size();
  std::vector<uint64_t> scenes;
  for (uint64_t seed_index = shard_index; seed_index < plan.seeds.size(); seed_index += shard_count) {
    for (uint64_t j = 0; j < per_seed; ++j) scenes.push_back(seed_index * per_seed + j);
  }
  return scenes;
}

}  // namespace vscan::service::dataset
