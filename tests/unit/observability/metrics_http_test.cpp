// The /metrics endpoint over a real socket: the registry's text with the Prometheus content type.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

#include <gtest/gtest.h>

#include "observability/metrics.h"
#include "observability/metrics_http.h"

namespace vscan::observability {
namespace {

// One HTTP/1.0 request; returns the whole response (the server closes the connection and answers
// in HTTP/1.0).
std::string Fetch(int port, const std::string& method, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    ::close(fd);
    return "";
  }
  const std::string request = method + " " + path + " HTTP/1.0\r\nHost: localhost\r\n\r\n";
  if (::send(fd, request.data(), request.size(), 0) != static_cast<ssize_t>(request.size())) {
    ::close(fd);
    return "";
  }
  std::string response;
  char buffer[4096];
  for (ssize_t n; (n = ::recv(fd, buffer, sizeof(buffer), 0)) > 0;) response.append(buffer, static_cast<size_t>(n));
  ::close(fd);
  return response;
}

std::string Body(const std::string& response) {
  const auto end = response.find("\r\n\r\n");
  return end == std::string::npos ? "" : response.substr(end + 4);
}

TEST(MetricsHttp, ServesTheRegistryAtMetrics) {
  Registry registry;
  registry.AddCounter("scrapes_total", "Scrapes").WithLabels({}).Increment(7);
  auto endpoint = MetricsEndpoint::Start("127.0.0.1:0", registry);
  ASSERT_TRUE(endpoint.ok()) << endpoint.status().ToString();
  ASSERT_GT((*endpoint)->port(), 0);

  const std::string response = Fetch((*endpoint)->port(), "GET", "/metrics");
  EXPECT_EQ(response.rfind("HTTP/1.0 200", 0), 0u) << response;
  EXPECT_NE(response.find("Content-Type: text/plain; version=0.0.4; charset=utf-8\r\n"), std::string::npos)
      << response;
  EXPECT_EQ(Body(response), "# HELP scrapes_total Scrapes\n# TYPE scrapes_total counter\nscrapes_total 7\n");

  // Later updates show in the next scrape.
  registry.AddGauge("up", "Up").WithLabels({}).Set(1);
  EXPECT_NE(Body(Fetch((*endpoint)->port(), "GET", "/metrics")).find("\nup 1\n"), std::string::npos);
}

TEST(MetricsHttp, ServesNothingElse) {
  Registry registry;
  auto endpoint = MetricsEndpoint::Start("127.0.0.1:0", registry);
  ASSERT_TRUE(endpoint.ok()) << endpoint.status().ToString();
  const int port = (*endpoint)->port();
  EXPECT_EQ(Fetch(port, "GET", "/").find("HTTP/1.0 404"), 0u);
  EXPECT_EQ(Fetch(port, "GET", "/metrics/x").find("HTTP/1.0 404"), 0u);
  EXPECT_EQ(Fetch(port, "POST", "/metrics").find("HTTP/1.0 405"), 0u);
  (*endpoint)->Stop();
  EXPECT_EQ(Fetch(port, "GET", "/metrics"), "");
}

TEST(MetricsHttp, RefusesAnAddressInUse) {
  Registry registry;
  auto first = MetricsEndpoint::Start("127.0.0.1:0", registry);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  const auto second = MetricsEndpoint::Start("127.0.0.1:" + std::to_string((*first)->port()), registry);
  EXPECT_FALSE(second.ok());
}

}  // namespace
}  // namespace vscan::observability
