#pragma once
// /api/clouds: stored clouds (service/clouds/cloud_store.h) thinned on the server and sent in a
// compact binary layout, their rows as JSON, and a job's clouds listed.

#include <cstdint>
#include <string>
#include <vector>

#include "store/cloud_catalogue.h"
#include "vscan/common/point_cloud.h"
#include "web/web_request.h"
#include "web/web_sources.h"

namespace vscan::web {

// Little-endian, every array starting at a multiple of 4 bytes:
//   char[4] "VSCL", uint32 version (1), uint32 fields (PointFields bits of the arrays that follow),
//   uint32 count (points sent), uint64 total (points before thinning), uint32 image width and
//   uint32 image height (the scan's camera; 0 when unknown), then float32 x y z per point, then per
//   field present, in the order of its bit: normal (float32 x3), range (float32), intensity
//   (float32), instance id (uint32), pixel (uint32 v * width + u), clean position (float32 x3),
//   incidence (float32, radians), status (uint8 PointStatus, padded with zeros to a multiple of 4
//   bytes), estimated normal (float32 x3).
inline constexpr char kCloudMagic[4] = {'V', 'S', 'C', 'L'};
inline constexpr uint32_t kCloudLayoutVersion = 1;
inline constexpr size_t kCloudHeaderBytes = 32;
inline constexpr long long kDefaultMaxPoints = 1'000'000;
inline constexpr long long kMaxMaxPoints = 5'000'000;

// Which of total points a thinned copy of at most max_points keeps: all of them when they fit,
// else max_points evenly spaced in storage order (point floor(k * total / max_points) for k = 0..),
// so that the same cloud thins the same way every time.
std::vector<uint32_t> ThinnedIndices(uint64_t total, uint64_t max_points);

// The cloud in the layout above, thinned to at most max_points.
std::string CloudBinary(const PointCloud& cloud, uint64_t max_points, uint32_t image_width, uint32_t image_height);

// {"cloud_id","name","points","fields":[...],"origin","frame","job_id","scene_id",
//  "world_from_sensor": 4 rows of 4 or null,"table_angle_deg": number or null,
//  "camera": {"width","height"} or null}
std::string CloudRecordJson(const store::CloudRecord& cloud);

// segments[0] is "clouds".
WebReply ServeClouds(const WebSources& sources, const WebRequest& request);

// The stored PLY artifact bytes as the cloud layout (a model's aligned.ply, uncovered.ply).
// RESOURCE_EXHAUSTED past the view's bounds, UNAVAILABLE while as many clouds as it decodes at once
// are being decoded, and the PLY reader's errors for bytes that are no cloud.
StatusOr<std::string> PlyAsCloudBinary(std::string_view ply, const std::string& name, uint64_t max_points);

}  // namespace vscan::web
