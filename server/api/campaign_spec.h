#pragma once
// A validated CampaignSpec: every field checked up front (errors name "spec.<field>") so that a
// bad request creates no job.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "api/service_context.h"
#include "robot/ik_types.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

inline constexpr uint32_t kMaxCampaignRotations = 3600;
inline constexpr uint32_t kMaxCampaignSteps = 10000;
inline constexpr int kMaxCampaignViewpoints = 1000;

struct CampaignViewpoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  robot::IkGoal goal;  // look from position at target, in world coordinates
};

// Sensor, noise, backend, fields and frame stay in spec: each step's scan is parsed from a
// ScanRequest built from it, exactly as ScanService parses one.
struct CampaignPlan {
  v1::CampaignSpec spec;
  std::vector<CampaignViewpoint> viewpoints;
  uint32_t rotations = 1;

  uint32_t steps_total() const { return rotations * static_cast<uint32_t>(viewpoints.size()); }
  double AngleDeg(uint32_t rotation) const {
    return spec.start_angle_deg() + rotation * spec.rotation_step_deg();
  }
};

// The ScanRequest of one step: the spec's sensor, noise, backend, fields and frame, the robot at
// joints (encoder noise when the spec asks), the table at its angle, and the step's seed.
v1::ScanRequest StepScanRequest(const v1::CampaignSpec& spec, const Eigen::VectorXd& joints, double table_angle_deg,
                                uint64_t seed);

// Checks the spec against the server's limits, the scene and the mount. validate_only (a dry run)
// skips the scene and mount checks when their ids are empty; every other check is the same.
StatusOr<CampaignPlan> ValidateCampaign(const v1::CampaignSpec& spec, ServiceContext& context,
                                        bool validate_only = false);

// Puts a field-naming error under the request field that holds the spec ("spec").
Status InSpec(const Status& status);

}  // namespace vscan::api
