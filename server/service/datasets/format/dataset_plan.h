#pragma once
// What a dataset holds: every bin fill, under every seed, seen by every sensor. Scene k is one
// (seed, bin, sensor) triple; scenes are numbered seed-major, then bin, then sensor.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "service/datasets/format/dataset_bins.h"
#include "service/datasets/format/dataset_picks_plan.h"
#include "vscan/common/status.h"
#include "vscan/plan/returned_light_plan.h"

namespace vscan::service::dataset {

// The images of each scene: camera poses sampled about the bin. Each view looks at the centre of the
// bin's floor from a direction within cone_deg of straight down (uniform over that spherical cap)
// at a distance uniform in [min_distance_m, max_distance_m], image x along the bin's x as far as
// the tilt allows. The default is one view straight down from camera_height_m.
struct DatasetViews {
  uint32_t count = 1;
  double cone_deg = 0;
  double min_distance_m = 0;  // 0 with max_distance_m 0: camera_height_m
  double max_distance_m = 0;
  bool operator==(const DatasetViews&) const = default;
};

// Views per scene and the steepest tilt a plan may ask for (image x follows the bin's x, which a
// view along it would lose).
inline constexpr uint32_t kMaxViewsPerScene = 1000;
inline constexpr double kMaxViewConeDeg = 80.0;

struct DatasetPlan {
  std::string name;
  std::vector<std::string> bins;     // bin fills by name; the job that fills bins resolves them
  std::vector<uint64_t> seeds;       // distinct, in the order scenes take them
  std::vector<std::string> sensors;  // sensor names
  double depth_scale_mm = 0.1;       // millimetres per unit of the 16-bit depth images
  // Empty, or one per bin: what the bin is filled with (the engine's frame source needs it).
  std::vector<DatasetBinFill> bin_fills;
  // Empty, or one per sensor: its preset and resolution.
  std::vector<DatasetSensor> sensor_setups;
  double camera_height_m = 0.6;  // above each bin's floor, looking straight down at its centre
  DatasetViews views;
  // A bin that takes fewer parts than its fill asks for: the scene is written and says so in
  // scene_fill.json and the job's result (false), or the run fails naming the scene (true).
  bool fail_on_underfilled_bin = false;
  // Every scan lit by the sensor's emitter and the parts' materials (the ReturnedLight message's
  // keys); unset: the sensor's fixed lighting, as before materials.
  std::optional<plan::ReturnedLightPlan> returned_light;
  // Set: every scene's parts are checked for picks (scene_pickable.json).
  std::optional<DatasetPicks> picks;
};

struct SceneKey {
  uint64_t scene_id = 0;
  size_t seed_index = 0;
  size_t bin_index = 0;
  size_t sensor_index = 0;
  uint64_t seed = 0;
};

// Six digits name a scene directory and an image in it; a plan holds at most this many images.
inline constexpr uint64_t kMaxScenes = 1'000'000;

// The distances views are sampled from: the plan's range, or camera_height_m when it sets none.
std::pair<double, double> ViewDistanceRange(const DatasetPlan& plan);

// first, first + 1, ..., first + count - 1.
std::vector<uint64_t> SeedRange(uint64_t first, uint64_t count);

// Non-empty lists, distinct names and seeds, names usable as they are in JSON and paths (printable
// ASCII without '/'), a finite positive depth scale, views within their bounds and at most kMaxScenes
// images (scenes x views).
Status CheckPlan(const DatasetPlan& plan);
// shard_count >= 1 and shard_index < shard_count.
Status CheckShard(uint32_t shard_index, uint32_t shard_count);

uint64_t SceneCount(const DatasetPlan& plan);
// scene_id < SceneCount(plan).
SceneKey SceneAt(const DatasetPlan& plan, uint64_t scene_id);
// Seeds are dealt round-robin: seed i goes to shard i mod shard_count, with every bin and sensor.
uint32_t ShardOfScene(const DatasetPlan& plan, uint64_t scene_id, uint32_t shard_count);
// The scenes of one shard in ascending order (none when the shard has no seed).
std::vector<uint64_t> ScenesOfShard(const DatasetPlan& plan, uint32_t shard_index, uint32_t shard_count);

}  // namespace vscan::service::dataset
