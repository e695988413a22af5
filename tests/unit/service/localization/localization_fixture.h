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

// Pins (the tube at kPinScale: 77 mm long, 6.5 mm across) lying beside angle blocks on a floor of
// side kPinFloor, as in a filled bin: two part types, one of them scaled.
inline constexpr double kPinScale = 0.127;
inline constexpr double kPinFloor = 0.3;

struct PinsAndBlocks {
  std::vector<Pose3> blocks;  // angle blocks at scale 1
  std::vector<Pose3> pins;
  PointCloud scan;            // world frame, positions and true normals, from FloorSensorPose(kPinFloor)
};

// Six blocks and three pins seen at 1280 x 960.
PinsAndBlocks ScanPinsBesideBlocks();

// The tube's symmetries at kPinScale (its flip moves with the scale).
localization::PartSymmetries PinSymmetries();

}  // namespace vscan::service::testing
