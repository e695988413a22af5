#pragma once
// What a model job needs to know of the campaign that captured its clouds: its state, scene and
// mount, and where the arm was told to put the sensor for each scan. The job catalogue keeps these
// as wire messages, so the api layer reads them for the service layer.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "capture/returned_light.h"
#include "store/stored_enums.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::service {

struct CampaignScanRecord {
  std::string name;  // the artifact's (and the cloud's) name
  std::optional<Pose3> commanded_world_from_sensor;
  Eigen::VectorXd commanded_joints;  // empty when not recorded
};

struct CampaignRecord {
  std::string job_id;
  std::string kind;  // "campaign" for a campaign
  store::JobState state = store::JobState::kQueued;
  std::string scene_id;
  std::string mount_id;
  bool encoder_noise = false;  // the campaign applied the mount's encoder noise
  // The returned light its scans were taken under, when it asked for one.
  std::optional<capture::ReturnedLightSpec> returned_light;
  std::vector<CampaignScanRecord> scans;  // in the order they were captured
};

class CampaignRecords {
 public:
  virtual ~CampaignRecords() = default;
  // NOT_FOUND for an unknown job.
  virtual StatusOr<CampaignRecord> Get(const std::string& job_id) = 0;
};

}  // namespace vscan::service
