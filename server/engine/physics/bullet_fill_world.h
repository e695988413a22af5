#pragma once
// FillBin's Bullet world: the bin as static boxes, each part a reduced convex hull about its
// centre of mass, sleeping on, a fixed step split into options.substeps.

#include <memory>
#include <vector>

#include "physics/bin_fill.h"
#include "physics/fill_world.h"
#include "physics/part_geometry.h"

namespace vscan::physics {

std::unique_ptr<FillWorld> MakeBulletFillWorld(const BinSpec& bin, const std::vector<PartGeometry>& geometry,
                                               const FillOptions& options);

}  // namespace vscan::physics
