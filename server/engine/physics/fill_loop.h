#pragma once
// The fill itself on any FillWorld: the spawn rule, parts that leave the bin, the settle rule,
// full, the time bound and cancellation. FillBin runs it on its tuned Bullet world; a benchmark
// can run it on another world with the same rules.

#include <atomic>
#include <vector>

#include "physics/bin_fill.h"
#include "physics/fill_world.h"
#include "physics/part_geometry.h"

namespace vscan::physics {

// Inputs must already be checked (CheckFillInput). Fills in everything but setup_wall_s.
FillResult RunFill(const BinSpec& bin, const std::vector<PartType>& parts, const std::vector<PartGeometry>& geometry,
                   const FillOptions& options, FillWorld& world, const std::atomic<bool>* cancel);

// The same rules on parts already in the bin (SettlePile): nothing is dropped; they settle from
// where they are, at the settle damping.
FillResult RunSettle(const BinSpec& bin, const std::vector<PartType>& parts, const std::vector<PartGeometry>& geometry,
                     const std::vector<PlacedPart>& placed, const FillOptions& options, FillWorld& world,
                     const std::atomic<bool>* cancel);

}  // namespace vscan::physics
