#pragma once
// A checked campaign in engine terms: every viewpoint at every table angle (rotation-major), each
// step scanned with the same sensor settings from where the arm puts the sensor.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot/ik_types.h"
#include "service/model/model_plan.h"
#include "service/scan/scan_plan.h"
#include "service/context/service_context.h"

namespace vscan::service {

inline constexpr uint32_t kMaxCampaignRotations = 3600;
inline constexpr uint32_t kMaxCampaignSteps = 10000;
inline constexpr int kMaxCampaignViewpoints = 1000;

struct CampaignViewpoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  robot::IkGoal goal;  // look from position at target, in world coordinates
};

struct CampaignPlan {
  std::string name;
  std::string scene_id;
  std::string mount_id;
  uint64_t seed = 0;
  std::vector<CampaignViewpoint> viewpoints;
  uint32_t rotations = 1;
  double start_angle_deg = 0.0;
  double rotation_step_deg = 0.0;
  bool reject_collisions = false;
  bool apply_encoder_noise = false;
  // Sensor, measurement model, backend, fields and frame of every step's scan. Each step places
  // the sensor on the arm, turns the table and seeds the noise.
  ScanPlan scan;
  // The model stages (align, reconstruct, evaluate) run on the scans as they are captured, when asked.
  std::optional<ModelPlan> model;
  // The steps the model stages add after the scans.
  uint32_t model_steps = 0;

  uint32_t scans_total() const { return rotations * static_cast<uint32_t>(viewpoints.size()); }
  uint32_t steps_total() const { return scans_total() + model_steps; }
  double AngleDeg(uint32_t rotation) const { return start_angle_deg + rotation * rotation_step_deg; }
};

// The scan of one step: plan.scan with the sensor where the arm at joints puts it (encoder noise
// when the plan asks), the table at its angle, and the step's seed.
StatusOr<ScanPlan> StepScanPlan(ServiceContext& context, const CampaignPlan& plan, const Eigen::VectorXd& joints,
                                double table_angle_deg, uint64_t seed);

// Checks the plan against what the server holds: the scene (with a table when it turns), the mount
// in that scene, collision checking when asked, and the sensor where the arm stands at rest.
// dry_run (a client checking a plan before it creates them) looks up only the ids it is given.
// Errors name the plan's fields ("scene_id", "mount_id", "rotations", "reject_collisions").
Status CheckCampaignWorld(ServiceContext& context, const CampaignPlan& plan, bool dry_run);

}  // namespace vscan::service
