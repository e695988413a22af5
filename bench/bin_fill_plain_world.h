#pragma once
// A plain Bullet world set up as PyBullet sets one up by default, for the bin fill benchmark:
// 240 Hz fixed steps without substeps, 50 solver iterations with PyBullet's solver settings, no
// sleeping, one btConvexHullShape per part from all its mesh vertices with the 1 mm margin of
// PyBullet's importer. The materials (friction, rolling friction, damping) are FillBin's so that
// both worlds can come to rest under the same rule.

#include <memory>
#include <vector>

#include "physics/bin_fill.h"
#include "physics/fill_world.h"
#include "physics/part_geometry.h"

namespace vscan::bench {

std::unique_ptr<physics::FillWorld> MakePlainFillWorld(const physics::BinSpec& bin,
                                                       const std::vector<physics::PartType>& parts,
                                                       const std::vector<physics::PartGeometry>& geometry,
                                                       const physics::FillOptions& materials);

}  // namespace vscan::bench
