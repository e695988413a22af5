#include "load_address.h"

#include <arpa/inet.h>

#include <charconv>
#include <cstring>

namespace vscan::cli {
namespace {

std::string StripScheme(std::string target) {
  for (const char* scheme : {"dns:///", "ipv4:", "ipv6:"}) {
    if (target.starts_with(scheme)) return target.substr(std::strlen(scheme));
  }
  return target;
}

bool IsLoopbackHost(const std::string& host) {
  if (host == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (inet_pton(AF_INET6, host.c_str(), &v6) == 1) return IN6_IS_ADDR_LOOPBACK(&v6);
  return false;
}

}  // namespace

std::optional<uint16_t> LoopbackPort(const std::string& target) {
  if (target.starts_with("unix:")) return target.size() > 5 ? std::optional<uint16_t>(0) : std::nullopt;
  const std::string address = StripScheme(target);
  std::string host;
  std::string port;
  if (address.starts_with('[')) {
    const size_t close = address.find(']');
    if (close == std::string::npos || address.compare(close + 1, 1, ":") != 0) return std::nullopt;
    host = address.substr(1, close - 1);
    port = address.substr(close + 2);
  } else {
    const size_t colon = address.rfind(':');
    if (colon == std::string::npos || address.find(':') != colon) return std::nullopt;
    host = address.substr(0, colon);
    port = address.substr(colon + 1);
  }
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (ec != std::errc() || end != port.data() + port.size() || value == 0 || value > 65535) return std::nullopt;
  if (!IsLoopbackHost(host)) return std::nullopt;
  return static_cast<uint16_t>(value);
}

}  // namespace vscan::cli
