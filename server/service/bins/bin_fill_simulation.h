#pragma once
// The physics of a planned bin fill: FillBin's run on its Bullet world, watched once per
// simulated second.

#include <atomic>

#include "physics/bin_fill.h"
#include "service/bins/bin_fill_plan.h"
#include "service/bins/bin_fill_progress.h"

namespace vscan::service {

physics::FillResult SimulateBinFill(const BinFillPlan& plan, const std::atomic<bool>* cancel,
                                    ProgressFillWorld::Observer observer);

}  // namespace vscan::service
