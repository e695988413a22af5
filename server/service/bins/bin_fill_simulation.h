#pragma once
// The physics of a planned bin fill: FillBin's run on its Bullet world, watched once per
// simulated second, and with replay, recorded for playback (bin_replay.h; the same result either way).

#include <atomic>

#include "physics/bin_fill.h"
#include "service/bins/bin_fill_plan.h"
#include "service/bins/bin_fill_progress.h"
#include "service/bins/bin_replay.h"

namespace vscan::service {

physics::FillResult SimulateBinFill(const BinFillPlan& plan, const std::atomic<bool>* cancel,
                                    ProgressFillWorld::Observer observer, BinReplay* replay = nullptr);

}  // namespace vscan::service
