#pragma once
// StructuredLightScanner <-> engine structured-light model. Error messages name the fields relative
// to the request ("sensor.structured_light.projector_offset").

#include "service/context/server_options.h"
#include "sensor/structured_light.h"
#include "vscan/common/status.h"
#include "vscan/v1/sensor.pb.h"

namespace vscan::api {

// camera is proto.camera() already parsed by the caller (the pinhole camera parsing, with its messages
// naming "sensor.structured_light.camera..."); it is checked again against limits.max_rays_per_scan.
// Every other field is validated here; an unset projector_offset or camera is INVALID_ARGUMENT.
StatusOr<sensor::StructuredLight> StructuredLightFromProto(const v1::StructuredLightScanner& proto,
                                                           const sensor::PinholeCamera& camera, const service::Limits& limits);

// Pinhole camera with explicit intrinsics, near/far and lighting (lens distortion is not part of the model).
void ToProto(const sensor::PinholeCamera& camera, v1::PinholeCamera* out);
void ToProto(const sensor::StructuredLight& sl, v1::StructuredLightScanner* out);

}  // namespace vscan::api
