#include "physics/bin_fill.h"

#include <chrono>

#include "physics/bullet_fill_world.h"
#include "physics/fill_checks.h"
#include "physics/fill_loop.h"
#include "physics/part_geometry.h"

namespace vscan::physics {

const char* FillEndName(FillEnd end) {
  switch (end) {
    case FillEnd::kSettled:
      return "settled";
    case FillEnd::kTimeBound:
      return "time_bound";
    case FillEnd::kFull:
      return "full";
    case FillEnd::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

BinInterior InteriorOf(const BinSpec& bin) {
  BinInterior interior;
  if (bin.mesh.empty()) {
    interior.lo = Eigen::Vector3d(-0.5 * bin.inner_size.x(), -0.5 * bin.inner_size.y(), 0.0);
    interior.hi = Eigen::Vector3d(0.5 * bin.inner_size.x(), 0.5 * bin.inner_size.y(), bin.inner_size.z());
    interior.wall = bin.wall_thickness;
    return interior;
  }
  Eigen::Vector3f lo, hi;
  bin.mesh.Bounds(lo, hi);
  interior.lo = lo.cast<double>();
  interior.hi = hi.cast<double>();
  return interior;
}

StatusOr<FillResult> FillBin(const BinSpec& bin, const std::vector<PartType>& parts, const FillOptions& options,
                             const std::atomic<bool>* cancel) {
  RETURN_IF_ERROR(CheckFillInput(bin, parts, options));
  const auto start = std::chrono::steady_clock::now();
  const std::vector<PartGeometry> geometry = MakePartGeometries(parts, options.hull_tolerance_m);
  RETURN_IF_ERROR(CheckPartMasses(geometry));
  const auto world = MakeBulletFillWorld(bin, geometry, options);
  const double setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  FillResult result = RunFill(bin, parts, geometry, options, *world, cancel);
  result.setup_wall_s = setup_s;
  return result;
}

StatusOr<FillResult> SettlePile(const BinSpec& bin, const std::vector<PartType>& parts,
                                const std::vector<PlacedPart>& placed, const FillOptions& options,
                                const std::atomic<bool>* cancel) {
  RETURN_IF_ERROR(CheckFillInput(bin, parts, options));
  if (placed.size() > kMaxFillParts) {
    return InvalidArgument("placed", "at most " + std::to_string(kMaxFillParts) + " parts");
  }
  for (size_t i = 0; i < placed.size(); ++i) {
    const std::string field = "placed[" + std::to_string(i) + "]";
    if (placed[i].type >= parts.size()) return InvalidArgument(field + ".type", "names no part type");
    const Pose3& pose = placed[i].world_from_part;
    if (!pose.matrix().allFinite() || !pose.linear().isUnitary(1e-6) || pose.linear().determinant() < 0) {
      return InvalidArgument(field + ".world_from_part", "must be a finite rigid pose");
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const std::vector<PartGeometry> geometry = MakePartGeometries(parts, options.hull_tolerance_m);
  RETURN_IF_ERROR(CheckPartMasses(geometry));
  const auto world = MakeBulletFillWorld(bin, geometry, options);
  const double setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  FillResult result = RunSettle(bin, parts, geometry, placed, options, *world, cancel);
  result.setup_wall_s = setup_s;
  return result;
}

}  // namespace vscan::physics
