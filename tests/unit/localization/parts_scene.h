#pragma once
// Noise-free ray-cast scans (and the scenes behind them) of the fixture parts (data/parts/) at known poses, for the localizer
// tests: copies of the angle block standing on a plate, or any mix of parts lying on a floor.

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "localization/part_symmetries.h"
#include "raycast/raycast_scene.h"
#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"

namespace vscan::localization::testing {

// angle_block (inches, 34 x 25 x 34 mm), round (centimetres, a tube 51 mm across and 610 mm
// long) and plate_holes (millimetres, 203 x 305 x 12.7 mm).
enum class FixturePart { kAngleBlock, kRound, kPlateHoles };

// The part in metres, in its own frame; loaded once.
std::shared_ptr<const TriangleMesh> LoadPart(FixturePart part);

// The tube turns freely about its axis and may be flipped end for end; the others have none.
PartSymmetries SymmetriesOf(FixturePart part);

// The angle block in metres (its file is in inches), in its own frame.
std::shared_ptr<const TriangleMesh> AngleBlock();

// Poses of `count` (1 to 4) copies standing on the plane z = 0, turned about z, 9 cm or more apart.
std::vector<Pose3> StandingPoses(size_t count);

// A 640 x 480 depth scan (world frame, positions and normals) of the copies at the given poses on
// a plate of side plate_side centred on the origin, seen from above at an angle.
PointCloud ScanParts(const std::vector<Pose3>& world_from_part, double plate_side);

struct PlacedPart {
  FixturePart part = FixturePart::kAngleBlock;
  Pose3 world_from_part = Pose3::Identity();
};

// `count` copies of each part lying on the floor z = 0 with a face (the tube: its side) down,
// turned at random about z and spread at random, without overlap, over the middle of a square floor
// of side floor_side centred on the origin. The same seed gives the same poses.
std::vector<PlacedPart> LyingParts(const std::vector<std::pair<FixturePart, size_t>>& counts, double floor_side,
                                   uint64_t seed);

// The parts and their floor (instance ids from 1 in the order given, the floor 0), and where
// ScanFloor's sensor stands: above, at a slant, 1.5 floor sides from the floor's centre.
std::vector<raycast::SceneInstance> FloorInstances(const std::vector<PlacedPart>& parts, double floor_side);
Pose3 FloorSensorPose(double floor_side);

// A depth scan (world frame, positions and normals) of the parts on their floor from
// FloorSensorPose with a 50 degree wide view of width x height pixels.
PointCloud ScanFloor(const std::vector<PlacedPart>& parts, double floor_side, uint32_t width, uint32_t height);

// Three pins (the tube at kPinScale: 77 mm long, 6.5 mm across) lying beside six angle blocks on a
// floor of side kPinFloor, seen from FloorSensorPose(kPinFloor) at 1280 x 960 as in a filled bin:
// two part types, one of them scaled.
inline constexpr double kPinScale = 0.127;
inline constexpr double kPinFloor = 0.3;

struct PinsBesideBlocks {
  std::shared_ptr<const TriangleMesh> pin;  // the tube at kPinScale
  std::vector<Pose3> blocks;                // angle blocks at scale 1
  std::vector<Pose3> pins;
  PointCloud scan;  // world frame, positions and true normals
};
PinsBesideBlocks ScanPinsBesideBlocks();

// The tube's symmetries at kPinScale (its flip moves with the scale).
PartSymmetries PinSymmetries();

}  // namespace vscan::localization::testing
