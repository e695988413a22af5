#include "observability/metrics_http.h"

#include <cstring>
#include <string>

#include <civetweb.h>

namespace vscan::observability {
namespace {

constexpr const char* kContentType = "text/plain; version=0.0.4; charset=utf-8";

int ServeMetrics(mg_connection* connection, void* registry_ptr) {
  const auto& registry = *static_cast<const Registry*>(registry_ptr);
  const mg_request_info* request = mg_get_request_info(connection);
  if (std::strcmp(request->request_method, "GET") != 0 && std::strcmp(request->request_method, "HEAD") != 0) {
    mg_send_http_error(connection, 405, "only GET is served here\n");
    return 405;
  }
  const std::string body = registry.Render();
  mg_send_http_ok(connection, kContentType, static_cast<long long>(body.size()));
  if (std::strcmp(request->request_method, "GET") == 0) mg_write(connection, body.data(), body.size());
  return 200;
}

void InitCivetweb() {
  static const unsigned features = mg_init_library(0);
  (void)features;
}

}  // namespace

struct MetricsEndpoint::Server {
  mg_context* context = nullptr;
};

MetricsEndpoint::MetricsEndpoint(std::unique_ptr<Server> server, int port) : server_(std::move(server)), port_(port) {}

MetricsEndpoint::~MetricsEndpoint() { Stop(); }

StatusOr<std::unique_ptr<MetricsEndpoint>> MetricsEndpoint::Start(const std::string& address,
                                                                 const Registry& registry) {
  InitCivetweb();
  // Two threads are plenty for one scraper; no document root, so nothing but /metrics is served.
  const char* options[] = {"listening_ports", address.c_str(), "num_threads", "2", "request_timeout_ms", "10000",
                           nullptr};
  mg_callbacks callbacks{};
  mg_init_data init{&callbacks, nullptr, options};
  char error_text[256] = "";
  unsigned error_code = 0;
  mg_error_data error{&error_code, error_text, sizeof(error_text)};
  auto server = std::make_unique<Server>();
  server->context = mg_start2(&init, &error);
  if (!server->context) {
    return Unavailable("--metrics-listen: cannot listen on '" + address + "': " + error_text);
  }
  mg_set_request_handler(server->context, "/metrics$", ServeMetrics, const_cast<Registry*>(&registry));
  mg_server_port ports[1]{};
  const int bound = mg_get_server_ports(server->context, 1, ports);
  const int port = bound > 0 ? ports[0].port : 0;
  return std::unique_ptr<MetricsEndpoint>(new MetricsEndpoint(std::move(server), port));
}

void MetricsEndpoint::Stop() {
  if (server_ && server_->context) {
    mg_stop(server_->context);
    server_->context = nullptr;
  }
}

}  // namespace vscan::observability
