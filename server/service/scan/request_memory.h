#pragma once
// What one request holds in memory at its peak, estimated before it runs and checked against
// --max-request-memory-mib. Estimates are upper bounds: every ray is taken to hit.

#include <cstdint>
#include <string_view>

#include "service/scan/scan_plan.h"
#include "service/context/server_options.h"
#include "vscan/common/status.h"

namespace vscan::service {

// A scan's peak: a streamed ray cast holds a window of rows; a scan that needs the whole image
// (measurement, raster, ground truth) holds every ray's point, its encoded copy and per-ray scratch.
// streamed: whether the scan streams its rows (StreamsRows); campaign steps and dataset frames
// never do.
uint64_t ScanMemoryBytes(const ScanPlan& plan, bool streamed);

// RESOURCE_EXHAUSTED naming field when bytes pass limits.max_request_memory_bytes.
Status CheckRequestMemory(uint64_t bytes, const Limits& limits, std::string_view field, std::string_view what);

}  // namespace vscan::service
