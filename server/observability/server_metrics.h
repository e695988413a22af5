#pragma once
// The metrics vscand exports, in one process-wide registry (docs/OPERATIONS.md lists them).

#include "observability/metrics.h"

namespace vscan::observability {

struct ServerMetrics {
  // Per gRPC method (e.g. "/vscan.v1.ScanService/Scan") and status code name (e.g. "OK").
  Family<Counter>& grpc_calls;
  Family<Counter>& grpc_errors;  // codes other than OK only
  Family<Histogram>& grpc_duration;
  // Per scan backend (raycast, raster_depth, ...) and result (ok, error, cancelled).
  Family<Counter>& scans;
  Counter& scan_rays;
  Histogram& scan_rays_per_second;
  Family<Histogram>& scan_duration;
  Counter& scan_points_sent;
  // Per job kind and final state.
  Family<Counter>& jobs_ended;
};

Registry& DefaultRegistry();
ServerMetrics& Metrics();

}  // namespace vscan::observability
