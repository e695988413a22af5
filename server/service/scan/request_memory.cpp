#include "service/scan/request_memory.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "service/scan/scan_ground_truth.h"
#include "service/scan/scan_pixel_images.h"

namespace vscan::service {
namespace {

// Rows a streamed cast keeps between the scanner and the client (a tile band and the outbox).
constexpr uint64_t kStreamedRows = 256;
// Per ray, apart from the point: the range image, hit records and the measurement's buffers.
constexpr uint64_t kScratchBytesPerRay = 48;
// The raster backends' framebuffers: depth, colour, object ids and their read-back copy.
constexpr uint64_t kRasterBytesPerPixel = 32;
// Neighbour search of estimated normals: the k-d tree and its index per point.
constexpr uint64_t kNormalSearchBytesPerPoint = 40;
// The indirect light: its radiance and phasor, the wanted mask and the pixel-to-point map per ray.
constexpr uint64_t kIndirectBytesPerRay = 40;

uint64_t BytesPerPoint(uint32_t fields) {
  PointCloud cloud;
  cloud.fields = fields | kFieldPosition;
  return cloud.BytesPerPoint();
}

std::string Mib(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.0f MiB", static_cast<double>(bytes) / (1 << 20) + 0.5);
  return text;
}

}  // namespace

uint64_t ScanMemoryBytes(const ScanPlan& plan, bool streamed) {
  const uint64_t rays = uint64_t{plan.camera.width} * plan.camera.height;
  if (streamed) {
    const uint64_t held = std::min<uint64_t>(rays, kStreamedRows * plan.camera.width);
    return held * (2 * BytesPerPoint(plan.fields) + kScratchBytesPerRay);
  }
  uint32_t fields = plan.fields | plan.measurement.fields;
  if (plan.measurement.any()) fields |= kFieldsGroundTruth | kFieldNormal | kFieldRange;
  if (plan.ground_truth) fields |= FieldsForGroundTruth(plan.fields, plan.measurement.include_rejected);
  if (plan.pixel_images) fields |= kFieldsForPixelImages;
  uint64_t per_ray = 2 * BytesPerPoint(fields) + kScratchBytesPerRay;
  if (plan.backend != ScanBackend::kRaycast) per_ray += kRasterBytesPerPixel;
  if (fields & kFieldEstimatedNormal) per_ray += kNormalSearchBytesPerPoint;
  // Structured light casts from the projector too and keeps its visibility per ray.
  if (plan.measurement.structured_light) per_ray += kScratchBytesPerRay;
  // The reason and grey images, and their copy in messages.
  if (plan.pixel_images) per_ray += 2 * (sizeof(uint8_t) + sizeof(uint16_t));
  if (plan.measurement.returned_light && plan.measurement.returned_light->indirect_samples > 0) {
    per_ray += kIndirectBytesPerRay;
  }
  return rays * per_ray;
}

Status CheckRequestMemory(uint64_t bytes, const Limits& limits, std::string_view field, std::string_view what) {
  if (bytes <= limits.max_request_memory_bytes) return Status::Ok();
  return ResourceExhausted(std::string(field), std::string(what) + " needs about " + Mib(bytes) +
                                                   " of memory, more than the limit of " +
                                                   Mib(limits.max_request_memory_bytes) +
                                                   " per request (--max-request-memory-mib)");
}

}  // namespace vscan::service
