#pragma once
// A mounted robot emptying the bin a bin fill made in its scene: each step settles the pile,
// scans it from the plan's sensor pose and localizes every part type in the scan (or takes the
// true poses), plans on the estimates, picks against the true parts and takes the picked part out
// of the scene; picking::EmptyBin runs the steps. The scene is written after every step (the
// picked part removed, the rest moved where they settled), so the arm's collision checks and the
// next scan see the pile as it is.

#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "localization/baseline_localizer.h"
#include "picking/empty_bin.h"
#include "service/bins/bin_fill_plan.h"
#include "service/context/service_context.h"
#include "service/scan/scan_plan.h"

namespace vscan::service {

enum class Perception {
  kBaseline,  // a scan and vscan's baseline localizer
  kTruth,     // the parts' true poses (planning and picking without localization errors)
  kClient,    // a scan, and the estimates the observer's client_estimates returns for it
};

struct PickingPlan {
  std::string mount_id;
  std::string scene_id;  // the mount's, where the bin fill placed its parts
  // The fill that made the pile: its bin and part types (meshes scaled, names); parts are the
  // scene's objects labelled "<part name>#<n>".
  BinFillPlan bin;
  grasping::Gripper gripper;
  grasping::GraspOptions grasp_options;
  grasping::PickOptions pick_options;
  std::chrono::microseconds ik_time_budget{20000};
  // Zero: the distance from the flange to the mount's tool centre point.
  double body_length_m = 0;
  Perception perception = Perception::kBaseline;
  ScanPlan scan;  // camera, world_from_sensor, measurement; its seed moves with the step
  uint64_t scan_seed = 1;
  localization::LocalizerOptions localizer;
  // kClient: how long a step waits for its estimates.
  std::chrono::milliseconds estimates_timeout{600000};
  picking::EmptyBinOptions session;
};

// What a step saw, for the job's artifacts: the pile it started from (true poses), the scan (empty
// with kTruth) and the estimates.
struct StepView {
  size_t step = 0;
  std::vector<physics::PlacedPart> truth;
  PointCloud scan;
  std::vector<picking::Estimate> estimates;
  // The grasps of each part type: what an estimate of that type costs the plan.
  std::vector<size_t> grasps_per_type;
};

struct PickingObserver {
  std::function<void(const StepView&)> perceived;  // before the step is planned
  std::function<void(const picking::PickStep&, const std::vector<physics::PlacedPart>&)> stepped;
  // Perception::kClient: the estimates for a step, called after perceived (its scan is stored).
  std::function<StatusOr<std::vector<picking::Estimate>>(const StepView&)> client_estimates;
  // The number of the run's first step: a resumed job numbers its steps on.
  size_t first_step = 0;
};

// NOT_FOUND naming "mount_id"; FAILED_PRECONDITION naming "mount_id" when the mount stands in
// another scene than the bin's, or "bin_job_id" when the scene holds none of the fill's parts;
// errors of the scan, the localizer and the scene writes as they are; CANCELLED once *cancel is set.
StatusOr<picking::EmptyBinResult> RunPickingSession(ServiceContext& context, const PickingPlan& plan,
                                                    const std::atomic<bool>* cancel,
                                                    const PickingObserver& observer = {});

}  // namespace vscan::service
