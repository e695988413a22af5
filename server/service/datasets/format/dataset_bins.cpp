#include "service/datasets/format/dataset_bins.h"

#include <cmath>

#include "vscan/plan/bin_fill_plan.h"

namespace vscan::service::dataset {
namespace {

bool Within(double value, double lo, double hi) { return std::isfinite(value) && value >= lo && value <= hi; }

}  // namespace


Status CheckBinFill(const DatasetBinFill& fill, const std::string& field) {
  for (int axis = 0; axis < 3; ++axis) {
    if (!Within(fill.inner_size_m[axis], 1e-3, 100.0)) {
      return InvalidArgument(field + ".bin.inner_size", "each size must be within [0.001, 100] m");
    }
  }
  if (!Within(fill.wall_thickness_m, 1e-4, 10.0)) {
    return InvalidArgument(field + ".bin.wall_thickness", "must be within [0.0001, 10] m");
  }
  if (!Within(fill.max_simulated_s, 0.1, 600.0)) {
    return InvalidArgument(field + ".max_simulated_s", "must be within [0.1, 600] s");
  }
  if (fill.parts.empty()) return InvalidArgument(field + ".parts", "lists nothing");
  uint64_t total = 0;
  for (size_t i = 0; i < fill.parts.size(); ++i) {
    const DatasetPart& part = fill.parts[i];
    const std::string path = field + ".parts[" + std::to_string(i) + "]";
    if (part.mesh_file.empty() == part.mesh_id.empty()) {
      return InvalidArgument(path, "needs mesh (a file) or mesh_id (a stored mesh), one of them");
    }
    if (!plan::MetresPerUnit(part.unit)) {
      return InvalidArgument(path + ".unit", "'" + part.unit + "' is not m, cm, mm, in or ft");
    }
    if (!Within(part.scale, 1e-6, 1e6)) return InvalidArgument(path + ".scale", "must be positive");
    if (part.count == 0) return InvalidArgument(path + ".count", "must be at least 1");
    if (part.collision != "convex_hull" && part.collision != "convex_decomposition") {
      return InvalidArgument(path + ".collision",
                             "unknown collision shape '" + part.collision + "' (convex_hull or convex_decomposition)");
    }
    total += part.count;
  }
  if (total > kMaxPartsInBin) {
    return InvalidArgument(field + ".parts", std::to_string(total) + " parts; at most " +
                                                 std::to_string(kMaxPartsInBin) + " in one bin");
  }
  return Status::Ok();
}

Status CheckSensor(const DatasetSensor& sensor, const std::string& field) {
  if (sensor.preset.empty()) return InvalidArgument(field + ".preset", "is empty");
  if ((sensor.width == 0) != (sensor.height == 0)) {
    return InvalidArgument(field, "width and height go together");
  }
  if (sensor.width > 8192 || sensor.height > 8192) return InvalidArgument(field, "at most 8192 pixels a side");
  return Status::Ok();
}

}  // namespace vscan::service::dataset
