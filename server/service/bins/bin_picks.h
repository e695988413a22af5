#pragma once
// The pick check a bin fill runs once its parts are placed: which of them a mounted robot with a
// gripper can take. The fill only calls it; what it runs (the scene's picks, CheckScenePicks) is
// wired in above the service layer (api/bins/bin_picks_spec.h).

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "grasping/pick_checks.h"
#include "vscan/common/status.h"

namespace vscan::service {

struct BinPartPick {
  std::string object_id;
  grasping::PickVerdict verdict;
  std::string covered_by_object_id;  // when covered: the object lying on it
};

struct BinPicks {
  std::string mount_id;
  std::string gripper;             // "suction" or "jaws"
  std::vector<BinPartPick> parts;  // in the order of the object ids asked
  size_t grasps_generated = 0;
  double elapsed_s = 0;
};

// The placed parts' object ids in; CANCELLED once *cancel is set.
using BinPickCheck =
    std::function<StatusOr<BinPicks>(const std::vector<std::string>& part_object_ids, const std::atomic<bool>* cancel)>;

}  // namespace vscan::service
