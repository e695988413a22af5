#pragma once
// Serves a registry at GET /metrics over plain HTTP (civetweb), for Prometheus to scrape.

#include <memory>
#include <string>

#include "observability/metrics.h"
#include "vscan/common/status.h"

namespace vscan::observability {

class MetricsEndpoint {
 public:
  // address: HOST:PORT with a numeric IPv4 host (port 0 picks a free one). The registry must
  // outlive the endpoint.
  static StatusOr<std::unique_ptr<MetricsEndpoint>> Start(const std::string& address, const Registry& registry);
  ~MetricsEndpoint();
  MetricsEndpoint(const MetricsEndpoint&) = delete;
  MetricsEndpoint& operator=(const MetricsEndpoint&) = delete;

  int port() const { return port_; }
  // Stops serving; waits for requests in progress.
  void Stop();

 private:
  struct Server;
  MetricsEndpoint(std::unique_ptr<Server> server, int port);
  std::unique_ptr<Server> server_;
  int port_ = 0;
};

}  // namespace vscan::observability
