#include "service/scan/scan_ground_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"

namespace vscan::service {
namespace {

// Pixels [u0, u1) x [v0, v1) of the image.
struct PixelBox {
  uint32_t u0 = 0, v0 = 0, u1 = 0, v1 = 0;
  bool empty() const { return u1 <= u0 || v1 <= v0; }
};

// The image pixels the instance's bounding box covers, or nothing when it lies wholly before
// near or beyond far. A box reaching behind the camera's centre covers the whole image.
std::optional<PixelBox> ProjectedBox(const raycast::SceneInstance& instance, const sensor::PinholeCamera& camera,
                                     const Pose3& sensor_from_world) {
  Eigen::Vector3f lo, hi;
  instance.mesh->Bounds(lo, hi);
  const Pose3 sensor_from_object = sensor_from_world * instance.world_from_object;
  double z_min = INFINITY, z_max = -INFINITY;
  double u_min = INFINITY, u_max = -INFINITY, v_min = INFINITY, v_max = -INFINITY;
  bool behind = false;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d local((corner & 1 ? hi : lo).x(), (corner & 2 ? hi : lo).y(), (corner & 4 ? hi : lo).z());
    const Eigen::Vector3d p = sensor_from_object * (instance.scale * local);
    z_min = std::min(z_min, p.z());
    z_max = std::max(z_max, p.z());
    if (p.z() <= 1e-9) {
      behind = true;
      continue;
    }
    const double u = camera.fx * p.x() / p.z() + camera.cx, v = camera.fy * p.y() / p.z() + camera.cy;
    u_min = std::min(u_min, u);
    u_max = std::max(u_max, u);
    v_min = std::min(v_min, v);
    v_max = std::max(v_max, v);
  }
  if (z_max < camera.near || z_min > camera.far) return std::nullopt;
  const auto w = static_cast<double>(camera.width), h = static_cast<double>(camera.height);
  if (behind) return PixelBox{0, 0, camera.width, camera.height};
  // Pixel k spans [k, k + 1); its ray passes through k + 0.5.
  const auto clamp = [](double x, double hi_value) { return static_cast<uint32_t>(std::clamp(x, 0.0, hi_value)); };
  PixelBox box{clamp(std::floor(u_min), w), clamp(std::floor(v_min), h), clamp(std::ceil(u_max), w),
               clamp(std::ceil(v_max), h)};
  if (box.empty()) return std::nullopt;
  return box;
}

// box widened (inside the image) to at least 1/16 of the image each way: a camera validates its
// principal point within 10 image sizes of its centre, and a crop of a few pixels at the image's
// edge would put it further off.
PixelBox AtLeastASixteenth(PixelBox box, uint32_t width, uint32_t height) {
  const auto widen = [](uint32_t& lo, uint32_t& hi, uint32_t size) {
    const uint32_t least = std::min(size, (size + 15) / 16);
    if (hi - lo >= least) return;
    const uint32_t start = (lo + hi) / 2 > least / 2 ? (lo + hi) / 2 - least / 2 : 0;
    lo = std::min(start, size - least);
    hi = lo + least;
  };
  widen(box.u0, box.u1, width);
  widen(box.v0, box.v1, height);
  return box;
}

// The camera restricted to box: the same rays through the same pixel centres.
sensor::PinholeCamera Crop(const sensor::PinholeCamera& camera, const PixelBox& box) {
  sensor::PinholeCamera crop = camera;
  crop.width = box.u1 - box.u0;
  crop.height = box.v1 - box.v0;
  crop.cx = camera.cx - box.u0;
  crop.cy = camera.cy - box.v0;
  return crop;
}

// The box around the pixels of a cloud cast with kFieldPixel (row-major indices of an image width wide).
PixelBox CoveredPixels(const PointCloud& cloud, uint32_t width) {
  PixelBox covered{std::numeric_limits<uint32_t>::max(), std::numeric_limits<uint32_t>::max(), 0, 0};
  for (const uint32_t pixel : cloud.pixels) {
    const uint32_t u = pixel % width, v = pixel / width;
    covered.u0 = std::min(covered.u0, u);
    covered.v0 = std::min(covered.v0, v);
    covered.u1 = std::max(covered.u1, u + 1);
    covered.v1 = std::max(covered.v1, v + 1);
  }
  return covered;
}

bool Counts(const PointCloud& cloud, size_t i) {
  if (!cloud.Has(kFieldStatus)) return true;
  const auto status = static_cast<PointStatus>(cloud.statuses[i]);
  return status == PointStatus::kMeasured || status == PointStatus::kOutlier || status == PointStatus::kFlyingPixel;
}

}  // namespace

uint32_t FieldsForGroundTruth(uint32_t fields, bool include_rejected) {
  return fields | kFieldInstanceId | (include_rejected ? uint32_t{kFieldStatus} : 0u);
}

StatusOr<std::vector<ObjectTruth>> ObjectGroundTruth(const scenes::ScanTarget& target,
                                                     const sensor::PinholeCamera& camera,
                                                     const Pose3& world_from_sensor, const PointCloud& cloud,
                                                     const std::atomic<bool>* cancel) {
  std::map<uint32_t, uint64_t> visible;
  if (cloud.Has(kFieldInstanceId)) {
    for (size_t i = 0; i < cloud.size(); ++i) {
      if (Counts(cloud, i)) ++visible[cloud.instance_ids[i]];
    }
  }
  std::map<uint32_t, const raycast::SceneInstance*> instances;
  for (const raycast::SceneInstance& instance : *target.instances) instances[instance.instance_id] = &instance;
  const Pose3 sensor_from_world = world_from_sensor.inverse();
  std::vector<ObjectTruth> out;
  for (const store::ObjectRecord& object : target.scene.objects) {
    if (cancel && cancel->load()) return Cancelled("scan cancelled");
    const auto found = instances.find(object.instance_id);
    if (found == instances.end()) continue;
    const raycast::SceneInstance& instance = *found->second;
    const auto projected = ProjectedBox(instance, camera, sensor_from_world);
    if (!projected) continue;
    const PixelBox box = AtLeastASixteenth(*projected, camera.width, camera.height);
    ASSIGN_OR_RETURN(const auto alone, raycast::RaycastScene::Build(std::span(&instance, 1)));
    raycast::ScanOptions options;
    options.fields = kFieldPosition | kFieldPixel;
    options.cancel = cancel;
    raycast::ScanStats stats;
    const sensor::PinholeCamera crop = Crop(camera, box);
    ASSIGN_OR_RETURN(const PointCloud alone_cloud, raycast::Scan(*alone, crop, world_from_sensor, options, &stats));
    const auto seen = visible.find(object.instance_id);
    const uint64_t visible_points = seen == visible.end() ? 0 : seen->second;
    if (stats.points == 0 && visible_points == 0) continue;
    ObjectTruth truth;
    truth.object_id = object.object_id;
    truth.mesh_id = object.mesh_id;
    truth.label = object.label;
    truth.instance_id = object.instance_id;
    truth.scale = object.scale;
    truth.world_from_object = instance.world_from_object;
    truth.sensor_from_object = sensor_from_world * instance.world_from_object;
    truth.visible_points = visible_points;
    truth.unoccluded_points = stats.points;
    truth.visible_fraction =
        stats.points > 0 ? static_cast<double>(visible_points) / static_cast<double>(stats.points) : 0.0;
    if (!alone_cloud.pixels.empty()) {
      const PixelBox covered = CoveredPixels(alone_cloud, crop.width);
      truth.alone_u0 = box.u0 + covered.u0;
      truth.alone_v0 = box.v0 + covered.v0;
      truth.alone_u1 = box.u0 + covered.u1;
      truth.alone_v1 = box.v0 + covered.v1;
      truth.alone_pixels.reserve(alone_cloud.pixels.size());
      for (const uint32_t p : alone_cloud.pixels) {
        truth.alone_pixels.push_back((box.v0 + p / crop.width) * camera.width + box.u0 + p % crop.width);
      }
      std::sort(truth.alone_pixels.begin(), truth.alone_pixels.end());
    }
    out.push_back(std::move(truth));
  }
  return out;
}

void KeepFields(PointCloud& cloud, uint32_t fields) {
  if (!(fields & kFieldInstanceId)) cloud.instance_ids.clear();
  if (!(fields & kFieldStatus)) cloud.statuses.clear();
  if (!(fields & kFieldPixel)) cloud.pixels.clear();
  if (!(fields & kFieldIntensity)) cloud.intensities.clear();
  cloud.fields &= fields | kFieldPosition;
}

}  // namespace vscan::service
