#include "capture/measurement_spec.h"

#include <cmath>
#include <string>

namespace vscan::capture {
namespace {

Status CheckRange(double value, double low, double high, bool high_open, std::string_view field,
                  std::string_view member, std::string_view range) {
  if (!std::isfinite(value)) return InvalidArgument(FieldPath(field, member), "NaN or infinite value");
  if (value < low || value > high || (high_open && value == high)) {
    return InvalidArgument(FieldPath(field, member), "must be in " + std::string(range));
  }
  return Status::Ok();
}

}  // namespace

Status ValidateMeasurementSpec(const MeasurementSpec& spec, std::string_view noise_field,
                               std::string_view normals_field) {
  const OutlierSpec& o = spec.outliers;
  RETURN_IF_ERROR(CheckRange(o.rate, 0, 1, false, noise_field, "outlier_rate", "[0, 1]"));
  RETURN_IF_ERROR(CheckRange(o.angle_deg, 0, 90, true, noise_field, "outlier_angle_deg", "[0, 90)"));
  RETURN_IF_ERROR(CheckRange(o.origin_m, 0, 1e3, false, noise_field, "outlier_origin_m", "[0, 1000] metres"));
  if (o.rate > 0 && o.angle_deg == 0 && o.origin_m == 0) {
    return InvalidArgument(FieldPath(noise_field, "outlier_rate") +
                           ": needs outlier_angle_deg or outlier_origin_m to perturb the rays");
  }
  RETURN_IF_ERROR(CheckRange(spec.grazing_limit_deg, 0, 90, true, noise_field, "grazing_limit_deg", "[0, 90)"));
  RETURN_IF_ERROR(
      CheckRange(spec.flying_pixels.edge_m, 0, 1e3, false, noise_field, "flying_pixel_edge_m", "[0, 1000] metres"));
  if (spec.flying_pixels.enabled && !(spec.flying_pixels.edge_m > 0)) {
    return InvalidArgument(FieldPath(noise_field, "flying_pixel_edge_m"), "must be positive");
  }
  const NormalEstimationSpec& n = spec.normal_estimation;
  if (n.k < 3 || n.k > 128) return InvalidArgument(FieldPath(normals_field, "k"), "must be in [3, 128]");
  RETURN_IF_ERROR(CheckRange(n.max_distance, 0, 1e3, false, normals_field, "max_distance", "[0, 1000] metres"));
  if ((spec.fields & kFieldEstimatedNormal) && !(spec.fields & kFieldPosition)) {
    return InvalidArgument("fields", "POINT_FIELD_ESTIMATED_NORMAL needs POINT_FIELD_POSITION");
  }
  return Status::Ok();
}

}  // namespace vscan::capture
