#include "service/datasets/dataset_job_frames.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include <spdlog/spdlog.h>

#include "raycast/raycast_scene.h"
#include "service/context/raster_provider.h"
#include "service/scan/scan_backends.h"
#include "service/datasets/format/view_poses.h"
#include "service/scan/scan_ground_truth.h"
#include "service/scan/scan_pixel_images.h"

namespace vscan::service {
namespace {

constexpr uint32_t kBinInstance = 1;
constexpr uint32_t kFirstPartInstance = 2;
// The table the bin stands on: seen in depth, never a ground-truth object (not in the scene's objects).
constexpr uint32_t kTableInstance = 0xFFFFFFFEu;
constexpr double kTableThicknessM = 0.02;
constexpr double kTableMinSideM = 2.0;

// A square slab under the bin in its frame: its top touches the bin's outer floor (z = -wall), its
// side the larger of kTableMinSideM and four times the bin's outer diagonal, so that it fills the view.
TriangleMesh TableMesh(const physics::BinSpec& spec) {
  const Eigen::Vector3d outer = spec.inner_size + Eigen::Vector3d::Constant(2 * spec.wall_thickness);
  const double half = 0.5 * std::max(kTableMinSideM, 4 * outer.head<2>().norm());
  const double top = -spec.wall_thickness, bottom = top - kTableThicknessM;
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(float((i & 1) ? half : -half), float((i & 2) ? half : -half),
                               float((i & 4) ? top : bottom));
  }
  // Two outward-facing triangles per face of the box.
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}
// Fills kept for the sensors of one (seed, bin) and the frames being captured ahead.
constexpr size_t kFillsKept = 16;

uint64_t MixIn(uint64_t x, uint64_t more) {
  x += 0x9e3779b97f4a7c15ull + more;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// One 64-bit seed per scene, from its seed, bin and sensor (splitmix64 steps).
uint64_t SceneSeed(const dataset::SceneKey& key) {
  return MixIn(MixIn(key.seed, key.bin_index), key.sensor_index);
}

// The first view's noise is the scene's seed, as it was when a scene had one view.
uint64_t ViewNoiseSeed(const dataset::SceneKey& key, uint32_t view) {
  return view == 0 ? SceneSeed(key) : MixIn(SceneSeed(key), view);
}

// The settled bin as a scan target: the bin (instance 1) and each part (2, 3, ...), only the
// parts listed as scene objects, so that only they get ground truth.
struct FilledBin {
  scenes::ScanTarget target;
  std::vector<uint32_t> obj_ids;  // per part instance, from kFirstPartInstance on
  uint64_t parts_planned = 0;
  physics::MeshOverlaps mesh_overlap;
  // Set when the plan gives any part a material.
  std::optional<std::vector<dataset::InstanceMaterial>> materials;
  // Set when the plan checks picks.
  std::shared_ptr<const std::vector<dataset::PartPickRecord>> picks;
};

// The index into each part type's materials this (seed, bin) takes (0 for a type with none).
std::vector<size_t> ChosenMaterials(const DatasetBinSetup& bin, uint64_t seed, size_t bin_index) {
  std::vector<size_t> chosen(bin.parts.size(), 0);
  for (size_t i = 0; i < bin.parts.size(); ++i) {
    chosen[i] = dataset::PartMaterialIndex(seed, bin_index, i, bin.materials[i].size());
  }
  return chosen;
}

StatusOr<FilledBin> FillAndBuild(const DatasetBinSetup& bin, uint64_t seed, size_t bin_index,
                                 const DatasetPickSetup* picks, const std::atomic<bool>* cancel) {
  physics::FillOptions options = bin.options;
  options.seed = seed;
  ASSIGN_OR_RETURN(const physics::FillResult result, physics::FillBin(bin.spec, bin.parts, options, cancel));
  if (result.end == physics::FillEnd::kCancelled) return Cancelled("dataset cancelled");
  size_t asked = 0;
  for (const physics::PartType& part : bin.parts) asked += part.count;
  if (result.parts.size() < asked) {
    spdlog::warn("seed {}: {} of {} parts in the bin ({}: {})", seed, result.parts.size(), asked,
                 physics::FillEndName(result.end), result.message);
  }
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;
  for (const physics::PartType& part : bin.parts) meshes.push_back(std::make_shared<const TriangleMesh>(part.mesh));
  auto instances = std::make_shared<std::vector<raycast::SceneInstance>>();
  instances->push_back({bin.bin_mesh, bin.spec.world_from_bin, 1.0, kBinInstance});
  instances->push_back(
      {std::make_shared<const TriangleMesh>(TableMesh(bin.spec)), bin.spec.world_from_bin, 1.0, kTableInstance});
  FilledBin filled;
  filled.parts_planned = asked;
  filled.mesh_overlap = result.mesh_overlap;
  filled.target.scene.revision = 1;
  const std::vector<size_t> chosen = ChosenMaterials(bin, seed, bin_index);
  const bool any_material = std::any_of(bin.materials.begin(), bin.materials.end(),
                                        [](const auto& materials) { return !materials.empty(); });
  if (any_material) filled.materials.emplace();
  for (size_t k = 0; k < result.parts.size(); ++k) {
    const physics::PlacedPart& placed = result.parts[k];
    const auto instance_id = static_cast<uint32_t>(kFirstPartInstance + k);
    const std::vector<sensor::Material>& materials = bin.materials[placed.type];
    instances->push_back({meshes[placed.type], placed.world_from_part, 1.0, instance_id,
                          materials.empty() ? sensor::DefaultMaterial() : materials[chosen[placed.type]]});
    if (filled.materials) {
      const auto& named = bin.material_plans[placed.type];
      const plan::MaterialPlan material =
          named.empty() ? plan::MaterialPlan{sensor::MaterialPresets().front().name, 0, 0, 0, 0}
                        : named[chosen[placed.type]];
      filled.materials->push_back({instance_id, bin.obj_ids[placed.type], bin.parts[placed.type].name, material});
    }
    store::ObjectRecord object;
    object.object_id = std::to_string(instance_id);
    object.label = bin.parts[placed.type].name + "#" + std::to_string(placed.instance + 1);
    object.pose = placed.world_from_part.matrix();
    object.instance_id = instance_id;
    filled.target.scene.objects.push_back(std::move(object));
    filled.obj_ids.push_back(bin.obj_ids[placed.type]);
  }
  if (picks) {
    std::vector<FillPart> parts;
    std::vector<grasping::PlacedMesh> fixtures;
    for (const raycast::SceneInstance& instance : *instances) {
      if (instance.instance_id == kBinInstance || instance.instance_id == kTableInstance) {
        fixtures.push_back({instance.mesh, instance.world_from_object});
      } else {
        parts.push_back({instance.instance_id, filled.obj_ids[instance.instance_id - kFirstPartInstance],
                         instance.world_from_object});
      }
    }
    ASSIGN_OR_RETURN(auto records, CheckFillPicks(*picks, parts, fixtures, cancel));
    filled.picks = std::make_shared<const std::vector<dataset::PartPickRecord>>(std::move(records));
  }
  ASSIGN_OR_RETURN(filled.target.raycast, raycast::RaycastScene::Build(*instances));
  filled.target.instances = std::move(instances);
  return filled;
}

dataset::ImageBox AloneBox(const ObjectTruth& truth) {
  if (truth.alone_u1 <= truth.alone_u0) return {};
  return {static_cast<int32_t>(truth.alone_u0), static_cast<int32_t>(truth.alone_v0),
          static_cast<int32_t>(truth.alone_u1 - 1 - truth.alone_u0),
          static_cast<int32_t>(truth.alone_v1 - 1 - truth.alone_v0)};
}

// The scan as images: each returned point's depth along the optical axis and its instance at its
// pixel; the cloud keeps positions, normals and instance ids.
void FillImages(const PointCloud& cloud, const Pose3& world_from_camera, dataset::DatasetFrame& frame) {
  const size_t pixels = size_t{frame.camera.width} * frame.camera.height;
  frame.depth_m.assign(pixels, 0.0f);
  frame.instance_ids.assign(pixels, 0);
  const Eigen::Isometry3f camera_from_world = world_from_camera.inverse().cast<float>();
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint32_t pixel = cloud.pixels[i];
    frame.depth_m[pixel] = (camera_from_world * cloud.positions[i]).z();
    frame.instance_ids[pixel] = cloud.instance_ids[i];
  }
  frame.cloud.fields = kFieldPosition | kFieldNormal | kFieldInstanceId;
  frame.cloud.positions = cloud.positions;
  frame.cloud.normals = cloud.normals;
  frame.cloud.instance_ids = cloud.instance_ids;
}

StatusOr<dataset::DatasetFrame> ScanFilledBin(const FilledBin& filled, const DatasetSensorSetup& sensor,
                                              const Pose3& world_from_camera, uint64_t noise_seed,
                                              RasterProvider& raster, const std::atomic<bool>* cancel) {
  ScanPlan plan = DatasetFramePlan(sensor);
  plan.world_from_sensor = world_from_camera;
  plan.measurement.seed = noise_seed;
  raycast::ScanStats stats;
  ASSIGN_OR_RETURN(PointCloud cloud,
                   RunScanBackend(WithPixelImageFields(plan), filled.target, raster, cancel, &stats));
  capture::PixelImages images = TakePixelImages(plan, cloud);
  ASSIGN_OR_RETURN(const std::vector<ObjectTruth> truths,
                   ObjectGroundTruth(filled.target, plan.camera, world_from_camera, cloud, cancel));
  dataset::DatasetFrame frame;
  frame.camera = {sensor.camera.fx, sensor.camera.fy, sensor.camera.cx, sensor.camera.cy, sensor.camera.width,
                  sensor.camera.height};
  frame.world_from_camera = world_from_camera;
  frame.parts_planned = filled.parts_planned;
  frame.parts_placed = filled.obj_ids.size();
  frame.deepest_part_overlap_m = filled.mesh_overlap.max_part_part_m;
  frame.deepest_bin_overlap_m = filled.mesh_overlap.max_part_bin_m;
  frame.materials = filled.materials;
  frame.picks = filled.picks;
  FillImages(cloud, world_from_camera, frame);
  frame.reasons = std::move(images.reasons);
  frame.gray = std::move(images.gray);
  for (const ObjectTruth& truth : truths) {
    dataset::GroundTruthObject object;
    object.obj_id = filled.obj_ids[truth.instance_id - kFirstPartInstance];
    object.instance_id = truth.instance_id;
    object.world_from_object = truth.world_from_object;
    object.visible_fraction = truth.visible_fraction;
    object.visible_pixels = truth.visible_points;
    object.alone_pixels = truth.unoccluded_points;
    object.alone_mask = truth.alone_pixels;
    object.full_box = AloneBox(truth);
    frame.objects.push_back(object);
  }
  return frame;
}

}  // namespace

Pose3 DatasetCameraPose(const DatasetBinSetup& bin, const dataset::DatasetPlan& plan, const dataset::SceneKey& key,
                        uint32_t view) {
  return bin.spec.world_from_bin * dataset::SampleViewPose(plan, dataset::ViewPoseSeed(SceneSeed(key), view));
}

dataset::FrameSource BinFrameSource(std::shared_ptr<const DatasetSetup> setup, const std::atomic<bool>* cancel) {
  using Fill = StatusOr<std::shared_ptr<const FilledBin>>;
  using FillKey = std::pair<size_t, size_t>;  // (seed index, bin index)
  struct State {
    std::shared_ptr<const DatasetSetup> setup;
    RasterProvider raster;  // never started: the dataset scans by ray casting
    std::mutex mutex;
    std::map<FillKey, std::shared_future<Fill>> fills;  // the latest few, each filled once
  };
  auto state = std::make_shared<State>();
  state->setup = std::move(setup);
  return [state, cancel](const dataset::SceneKey& key, uint32_t view) -> StatusOr<dataset::DatasetFrame> {
    const DatasetSetup& setup = *state->setup;
    // A plan's picks need their robot (AddDatasetPicks): never a dataset that silently lacks them.
    if (setup.plan.picks && !setup.picks) return FailedPrecondition("picks", "the plan's robot was not resolved");
    const DatasetBinSetup& bin = setup.bins[key.bin_index];
    const FillKey fill_key{key.seed_index, key.bin_index};
    std::shared_future<Fill> fill;
    std::optional<std::promise<Fill>> to_fill;
    {
      const std::lock_guard lock(state->mutex);
      auto found = state->fills.find(fill_key);
      if (found == state->fills.end()) {
        to_fill.emplace();
        found = state->fills.emplace(fill_key, to_fill->get_future().share()).first;
        // Scenes come in ascending order, so the oldest fill is the one no scene needs any more.
        if (state->fills.size() > kFillsKept) state->fills.erase(state->fills.begin());
      }
      fill = found->second;
    }
    if (to_fill) {
      StatusOr<FilledBin> filled = FillAndBuild(bin, key.seed, key.bin_index, setup.picks.get(), cancel);
      to_fill->set_value(filled.ok() ? Fill(std::make_shared<const FilledBin>(std::move(*filled)))
                                     : Fill(filled.status()));
    }
    const Fill& filled = fill.get();
    if (!filled.ok()) return filled.status();
    return ScanFilledBin(**filled, setup.sensors[key.sensor_index], DatasetCameraPose(bin, setup.plan, key, view),
                         ViewNoiseSeed(key, view), state->raster, cancel);
  };
}

ScanPlan DatasetFramePlan(const DatasetSensorSetup& sensor) {
  ScanPlan plan;
  plan.camera = sensor.camera;
  plan.fields = kFieldPosition | kFieldNormal | kFieldInstanceId | kFieldPixel;
  plan.measurement = sensor.measurement;
  plan.measurement.fields = plan.fields;
  plan.ground_truth = true;
  return plan;
}

size_t DatasetFramesAhead() {
  const unsigned cores = std::thread::hardware_concurrency();
  return cores <= 1 ? 0 : std::min<size_t>(cores - 1, 7);
}

}  // namespace vscan::service
