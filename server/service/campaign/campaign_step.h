#pragma once
// One step of a campaign: the arm's pose for a viewpoint, the optional collision check, and the
// scan from that pose with the table at its angle, run as any other scan is.

#include <atomic>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "service/campaign/campaign_plan.h"
#include "service/context/service_context.h"
#include "raycast/scanner.h"
#include "robot_registry/robot_registry.h"
#include "vscan/common/point_cloud.h"

namespace vscan::service {

// The look-at IK answer for a viewpoint. The arm stands beside the table, so one answer serves
// every table angle.
struct ViewpointSolution {
  bool reached = false;
  double miss_distance = 0.0;  // metres; 0 when reached
  Eigen::VectorXd joints;
};

struct StepResult {
  enum class Outcome { kCaptured, kUnreachable, kCollision };
  Outcome outcome = Outcome::kUnreachable;
  std::string collision;  // what touches what, for kCollision
  robot_registry::ArmState arm;   // commanded and achieved joints and sensor poses (not for kUnreachable)
  uint64_t seed = 0;
  PointCloud cloud;
  raycast::ScanStats stats;
  // Rays the returned light judged too dark or saturated (0 without the returned light).
  uint64_t rejected_dark = 0;
  uint64_t rejected_saturated = 0;
};

// A distinct, reproducible seed per step (encoder noise and measurement noise).
uint64_t StepSeed(uint64_t campaign_seed, uint32_t step);

StatusOr<ViewpointSolution> SolveViewpoint(const robot_registry::MountedRobot& mounted,
                                           const CampaignViewpoint& viewpoint);

// Runs a step whose viewpoint has been solved: the arm at the solution, the collision check when
// the plan asks, then the scan. Stops early (CANCELLED) when *cancel is set.
StatusOr<StepResult> RunStep(ServiceContext& context, const CampaignPlan& plan, const ViewpointSolution& solution,
                             double table_angle_deg, uint64_t seed, const std::atomic<bool>* cancel);

}  // namespace vscan::service
