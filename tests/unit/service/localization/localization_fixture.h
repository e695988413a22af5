#pragma once
// The fixture parts (data/parts/) stored in a ServiceWorld the way an upload stores them, in the
// units parts_scene.h loads them in, so that its true poses hold for the stored meshes.

#include <array>
#include <string>
#include <vector>

#include "parts_scene.h"
#include "service_world.h"

namespace vscan::service::testing {

// Mesh ids indexed by FixturePart.
std::array<std::string, 3> StoreFixtureParts(ServiceWorld& world);

using localization::testing::kPinFloor;
using localization::testing::kPinScale;
using localization::testing::PinSymmetries;
using localization::testing::ScanPinsBesideBlocks;
using PinsAndBlocks = localization::testing::PinsBesideBlocks;

}  // namespace vscan::service::testing
