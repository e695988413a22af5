#pragma once
// An uploaded cloud file, from bytes to a checked cloud: its format told from its first bytes when
// the client does not say, parsed by the readers vscan writes its own files with, bounded, and
// every position finite and within the physical bounds. Errors name "cloud data" for what the file
// holds and "format" for what the client said.

#include <cstdint>
#include <optional>
#include <string_view>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::service {

inline constexpr std::string_view kCloudDataField = "cloud data";

enum class CloudFileFormat { kDetect, kPly, kPcd };

// PLY when the bytes start with a "ply" line; PCD when they start with a "# .PCD" comment or a
// VERSION or FIELDS line; else nothing.
std::optional<CloudFileFormat> DetectCloudFormat(std::string_view bytes);

// The cloud the bytes hold: binary or ASCII PLY; binary, ASCII or binary_compressed PCD. Points whose
// x, y and z are all NaN (the holes of an organised cloud) are dropped. INVALID_ARGUMENT for a
// format that cannot be told, a malformed or truncated file (a count that lies, a declared size the
// bytes cannot hold), a file without points, and a position (or clean position) that is NaN,
// infinite or beyond kMaxCoordinateM; RESOURCE_EXHAUSTED when the cloud's arrays would pass max_bytes.
StatusOr<PointCloud> ParseUploadedCloud(std::string_view bytes, CloudFileFormat format, uint64_t max_bytes);

}  // namespace vscan::service
