#include "api/scan/measurement_request.h"

namespace vscan::api {

StatusOr<capture::MeasurementSpec> MeasurementFromProto(const v1::ScanRequest& request, uint32_t fields) {
  const v1::NoiseSpec& n = request.noise();
  capture::MeasurementSpec spec;
  spec.outliers = {n.outlier_rate(), n.outlier_angle_deg(), n.outlier_origin_m()};
  spec.grazing_limit_deg = n.grazing_limit_deg();
  spec.flying_pixels.enabled = n.flying_pixels();
  if (n.flying_pixel_edge_m() != 0) spec.flying_pixels.edge_m = n.flying_pixel_edge_m();
  spec.include_rejected = request.include_rejected();
  if (request.has_normal_estimation()) {
    if (!(fields & kFieldEstimatedNormal)) {
      return InvalidArgument("normal_estimation", "set, but fields has no POINT_FIELD_ESTIMATED_NORMAL");
    }
    const v1::NormalEstimation& e = request.normal_estimation();
    if (e.k() != 0) {
      if (e.k() < 3 || e.k() > 128) return InvalidArgument("normal_estimation.k", "must be in [3, 128] (0: 16)");
      spec.normal_estimation.k = static_cast<int>(e.k());
    }
    spec.normal_estimation.max_distance = e.max_distance();
  }
  spec.fields = fields;
  RETURN_IF_ERROR(capture::ValidateMeasurementSpec(spec, "noise", "normal_estimation"));
  return spec;
}

}  // namespace vscan::api
