#pragma once
// Next best views of a model job: candidate viewpoints on rings about the true object's centre
// (elevations 0 to 60 degrees, an azimuth every 30 degrees, at the scans' median distance), each
// kept when the mount's arm reaches it, at every table angle (every 45 degrees when the scene has a
// table); of these, the few that would see most of what the scans missed.

#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "evaluation/view_hits.h"
#include "sensor/camera.h"
#include "service/model/model_report.h"
#include "robot_registry/robot_registry.h"
#include "store/catalogue.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"

namespace vscan::service {

struct NextBestViewRequest {
  std::string mount_id;
  uint32_t count = 3;
  double tau = 0.001;
  const TriangleMesh* truth = nullptr;  // model frame
  std::span<const Eigen::Vector3f> samples;
  std::span<const uint8_t> covered;
  sensor::PinholeCamera camera;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // of the truth, model frame
  std::optional<store::TableRecord> table;
  std::vector<Pose3> scan_poses;  // model_from_sensor of the aligned scans
  // Set: a candidate sees only what the scans' own light would measure (evaluation::MeasurableLight).
  std::optional<evaluation::MeasurableLight> light;
};

struct ProposedViews {
  std::vector<NextBestViewReport> views;
  std::string note;  // why there are none, when there are none
  size_t candidates = 0;
};

// CANCELLED when cancel becomes true.
StatusOr<ProposedViews> ProposeNextBestViews(robot_registry::RobotRegistry& robots, const NextBestViewRequest& request,
                                             const std::atomic<bool>* cancel);

}  // namespace vscan::service
