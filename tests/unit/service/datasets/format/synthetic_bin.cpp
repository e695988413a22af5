#include "synthetic_bin.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "service/datasets/format/dataset_materials.h"
#include "service/datasets/format/view_poses.h"
#include "vscan_test/meshes.h"

namespace vscan::test {
namespace {

using service::dataset::CameraIntrinsics;
using service::dataset::DatasetFrame;
using service::dataset::GroundTruthObject;
using service::dataset::ImageBox;
using service::dataset::SceneKey;

constexpr double kNoHit = std::numeric_limits<double>::infinity();

struct Hit {
  double t = kNoHit;
  uint32_t instance = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

Eigen::Vector3d BaseHalfExtent(uint32_t obj_id) {
  return obj_id == 1 ? Eigen::Vector3d(0.08, 0.05, 0.03) : Eigen::Vector3d(0.03, 0.03, 0.07);
}

// Slab test in the box's own frame.
Hit CastBox(const SyntheticBox& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  const Pose3 object_from_world = box.world_from_object.inverse();
  const Eigen::Vector3d o = object_from_world * origin;
  const Eigen::Vector3d d = object_from_world.linear() * direction;
  double t_near = -kNoHit, t_far = kNoHit;
  int near_axis = 0;
  double near_sign = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double h = box.half_extent_m[axis];
    if (std::abs(d[axis]) < 1e-12) {
      if (std::abs(o[axis]) > h) return {};
      continue;
    }
    double t0 = (-h - o[axis]) / d[axis], t1 = (h - o[axis]) / d[axis];
    const double sign = d[axis] > 0 ? -1.0 : 1.0;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) {
      t_near = t0;
      near_axis = axis;
      near_sign = sign;
    }
    t_far = std::min(t_far, t1);
  }
  if (t_near > t_far || t_near <= 0) return {};
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  normal[near_axis] = near_sign;
  return {t_near, box.instance_id, box.world_from_object.linear() * normal};
}

Hit CastFloor(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  if (direction.z() >= 0) return {};
  const double t = -origin.z() / direction.z();
  const Eigen::Vector3d p = origin + t * direction;
  if (std::abs(p.x()) > kFloorHalfSideM || std::abs(p.y()) > kFloorHalfSideM) return {};
  return {t, kFloorInstance, Eigen::Vector3d::UnitZ()};
}

// The nearest hit of the ray through pixel (u, v); boxes only when only_box is given.
Hit CastPixel(const CameraIntrinsics& camera, const Pose3& world_from_camera, const std::vector<SyntheticBox>& boxes,
              uint32_t u, uint32_t v, const SyntheticBox* only_box) {
  // z = 1 in the camera frame, so the ray parameter is the depth along the optical axis.
  const Eigen::Vector3d in_camera((u + 0.5 - camera.cx) / camera.fx, (v + 0.5 - camera.cy) / camera.fy, 1.0);
  const Eigen::Vector3d origin = world_from_camera.translation();
  const Eigen::Vector3d direction = world_from_camera.linear() * in_camera;
  if (only_box != nullptr) return CastBox(*only_box, origin, direction);
  Hit best = CastFloor(origin, direction);
  for (const SyntheticBox& box : boxes) {
    const Hit hit = CastBox(box, origin, direction);
    if (hit.t < best.t) best = hit;
  }
  return best;
}

// Pixels and box of one box alone in the view.
std::pair<uint64_t, ImageBox> AloneInView(const CameraIntrinsics& camera, const Pose3& world_from_camera,
                                          const SyntheticBox& box, std::vector<uint32_t>* mask) {
  uint64_t pixels = 0;
  int32_t min_x = INT32_MAX, min_y = INT32_MAX, max_x = -1, max_y = -1;
  for (uint32_t v = 0; v < camera.height; ++v) {
    for (uint32_t u = 0; u < camera.width; ++u) {
      if (CastPixel(camera, world_from_camera, {}, u, v, &box).t == kNoHit) continue;
      ++pixels;
      mask->push_back(v * camera.width + u);
      min_x = std::min(min_x, int32_t(u));
      min_y = std::min(min_y, int32_t(v));
      max_x = std::max(max_x, int32_t(u));
      max_y = std::max(max_y, int32_t(v));
    }
  }
  if (pixels == 0) return {0, ImageBox{}};
  return {pixels, ImageBox{min_x, min_y, max_x - min_x, max_y - min_y}};
}

}  // namespace

service::dataset::DatasetPlan SyntheticPlan() {
  service::dataset::DatasetPlan plan;
  plan.name = "synthetic";
  plan.bins = {"near-pair", "far-pair"};
  plan.seeds = service::dataset::SeedRange(11, 3);
  plan.sensors = {"narrow", "wide"};
  plan.camera_height_m = kCameraHeightM;
  return plan;
}

service::dataset::DatasetPlan SyntheticMultiViewPlan() {
  service::dataset::DatasetPlan plan = SyntheticPlan();
  plan.name = "synthetic-views";
  plan.views = {3, 35.0, 0.7, 0.9};
  return plan;
}

std::vector<SyntheticBox> SyntheticBoxes(const SceneKey& key) {
  const double shift = double(int64_t(key.seed % 7) - 3) * 0.012;
  const double bin_offset = 0.02 * double(key.bin_index);
  const double turn = double(key.seed % 5) * 0.3;
  std::vector<SyntheticBox> boxes;
  for (uint32_t obj_id = 1; obj_id <= 2; ++obj_id) {
    SyntheticBox box;
    box.obj_id = obj_id;
    box.instance_id = 9 + obj_id;
    box.half_extent_m = BaseHalfExtent(obj_id);
    const Eigen::Vector3d centre(obj_id == 1 ? shift : shift + 0.06, obj_id == 1 ? -bin_offset : 0.03 + bin_offset,
                                 box.half_extent_m.z());
    box.world_from_object = Eigen::Translation3d(centre) *
                            Eigen::AngleAxisd(obj_id == 1 ? turn : -turn, Eigen::Vector3d::UnitZ());
    boxes.push_back(box);
  }
  return boxes;
}

CameraIntrinsics SyntheticCamera(size_t sensor_index) {
  if (sensor_index == 0) return {60.0, 60.0, 32.0, 24.0, 64, 48};
  return {45.0, 46.0, 40.5, 29.5, 80, 60};
}

Pose3 SyntheticWorldFromCamera() {
  Pose3 pose = Pose3::Identity();
  pose.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  pose.translation() = Eigen::Vector3d(0, 0, kCameraHeightM);
  return pose;
}

bool SyntheticUnderfilled(const SceneKey& key) { return key.seed == 12 && key.bin_index == 1; }

DatasetFrame SyntheticFrame(const SceneKey& key) { return SyntheticFrame(SyntheticPlan(), key, 0); }

service::dataset::FrameSource SyntheticSource(const service::dataset::DatasetPlan& plan) {
  return [&plan](const SceneKey& key, uint32_t view) -> StatusOr<DatasetFrame> { return SyntheticFrame(plan, key, view); };
}

DatasetFrame SyntheticFrame(const service::dataset::DatasetPlan& plan, const SceneKey& key, uint32_t view) {
  DatasetFrame frame;
  frame.camera = SyntheticCamera(key.sensor_index);
  frame.world_from_camera = service::dataset::SampleViewPose(plan, service::dataset::ViewPoseSeed(key.scene_id, view));
  const CameraIntrinsics& camera = frame.camera;
  const std::vector<SyntheticBox> boxes = SyntheticBoxes(key);
  frame.parts_placed = boxes.size();
  frame.parts_planned = boxes.size() + (SyntheticUnderfilled(key) ? 1 : 0);
  const size_t pixels = size_t{camera.width} * camera.height;
  frame.depth_m.assign(pixels, 0.0f);
  frame.instance_ids.assign(pixels, 0);
  frame.reasons.assign(pixels, 0);
  frame.gray.assign(pixels, 0);
  frame.cloud.fields = kFieldPosition | kFieldNormal | kFieldInstanceId | kFieldRange;
  for (uint32_t v = 0; v < camera.height; ++v) {
    for (uint32_t u = 0; u < camera.width; ++u) {
      const Hit hit = CastPixel(camera, frame.world_from_camera, boxes, u, v, nullptr);
      if (hit.t == kNoHit) continue;
      const size_t i = size_t{v} * camera.width + u;
      frame.depth_m[i] = float(hit.t);
      frame.instance_ids[i] = hit.instance;
      frame.reasons[i] = static_cast<uint8_t>(PointStatus::kMeasured);
      // A grey that falls with depth, so that the image is not flat.
      frame.gray[i] = static_cast<uint16_t>(std::min(65535.0, 20000.0 / hit.t));
      const Eigen::Vector3d in_camera((u + 0.5 - camera.cx) / camera.fx * hit.t,
                                      (v + 0.5 - camera.cy) / camera.fy * hit.t, hit.t);
      frame.cloud.positions.push_back((frame.world_from_camera * in_camera).cast<float>());
      frame.cloud.normals.push_back(hit.normal.cast<float>());
      frame.cloud.instance_ids.push_back(hit.instance);
      frame.cloud.ranges.push_back(float(in_camera.norm()));
    }
  }
  for (const SyntheticBox& box : boxes) {
    GroundTruthObject object;
    object.obj_id = box.obj_id;
    object.instance_id = box.instance_id;
    object.world_from_object = box.world_from_object;
    for (const uint32_t id : frame.instance_ids) object.visible_pixels += id == box.instance_id ? 1 : 0;
    const auto [alone, full_box] = AloneInView(camera, frame.world_from_camera, box, &object.alone_mask);
    object.full_box = full_box;
    object.alone_pixels = alone;
    object.visible_fraction = alone == 0 ? 0.0 : double(object.visible_pixels) / double(alone);
    frame.objects.push_back(object);
  }
  // Each part type one of three materials per (seed, bin), as the dataset job chooses them.
  static const char* const kMaterials[] = {"machined-aluminium", "black-anodised-aluminium", "white-abs"};
  frame.materials.emplace();
  for (const SyntheticBox& box : boxes) {
    const size_t chosen = service::dataset::PartMaterialIndex(key.seed, key.bin_index, box.obj_id, 3);
    frame.materials->push_back({box.instance_id, box.obj_id, "box" + std::to_string(box.obj_id),
                                plan::MaterialPlan{kMaterials[chosen], 0, 0, 0, 0}});
  }
  return frame;
}

std::vector<service::dataset::PartModel> SyntheticParts() {
  std::vector<service::dataset::PartModel> parts;
  for (uint32_t obj_id = 1; obj_id <= 2; ++obj_id) {
    service::dataset::PartModel part;
    part.obj_id = obj_id;
    const Eigen::Vector3d h = BaseHalfExtent(obj_id);
    part.mesh = MakeBox(-h, h);
    const int folds = obj_id == 1 ? 2 : 4;
    for (int k = 1; k < folds; ++k) {
      part.discrete_symmetries.emplace_back(
          Eigen::AngleAxisd(2 * std::numbers::pi * k / folds, Eigen::Vector3d::UnitZ()));
    }
    parts.push_back(part);
  }
  return parts;
}

}  // namespace vscan::test
