#include "observability/server_metrics.h"

namespace vscan::observability {
namespace {

ServerMetrics MakeServerMetrics(Registry& registry) {
  // 1 ms to about 2 min: quick catalogue reads up to long scans and uploads.
  const std::vector<double> call_seconds = ExponentialBuckets(0.001, 2.5, 14);
  return ServerMetrics{
      registry.AddCounter("vscan_grpc_calls_total", "gRPC calls handled, by method and status code",
                          {"method", "code"}),
      registry.AddCounter("vscan_grpc_errors_total", "gRPC calls that ended with a status other than OK",
                          {"method", "code"}),
      registry.AddHistogram("vscan_grpc_call_duration_seconds",
                            "Time from a call's arrival to its status, by method", {"method"}, call_seconds),
      registry.AddCounter("vscan_scans_total", "Scans run (streamed, whole-cloud and campaign scans)",
                          {"backend", "result"}),
      registry.AddCounter("vscan_scan_rays_total", "Rays cast by scans").WithLabels({}),
      registry
          .AddHistogram("vscan_scan_rays_per_second", "Rays per second of each finished scan", {},
                        ExponentialBuckets(1e5, 2, 12))
          .WithLabels({}),
      registry.AddHistogram("vscan_scan_duration_seconds", "Time each finished scan took, by backend", {"backend"},
                            ExponentialBuckets(0.005, 2.5, 10)),
      registry.AddCounter("vscan_scan_points_sent_total", "Points sent to clients by Scan calls").WithLabels({}),
      registry.AddCounter("vscan_jobs_ended_total", "Jobs that ended, by kind and final state", {"kind", "state"}),
  };
}

}  // namespace

Registry& DefaultRegistry() {
  static Registry registry;
  return registry;
}

ServerMetrics& Metrics() {
  static ServerMetrics metrics = MakeServerMetrics(DefaultRegistry());
  return metrics;
}

}  // namespace vscan::observability
