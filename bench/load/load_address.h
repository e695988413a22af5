#pragma once
// Which server addresses vscan-load may drive: only this machine's.

#include <cstdint>
#include <optional>
#include <string>

namespace vscan::cli {

// A loopback target: "unix:" sockets, and host:port where the host is localhost, an IPv4
// address in 127.0.0.0/8 or ::1 (bracketed), optionally after a "dns:///", "ipv4:" or "ipv6:"
// scheme. The TCP port, or 0 for unix sockets; nullopt for anything else.
std::optional<uint16_t> LoopbackPort(const std::string& target);

}  // namespace vscan::cli
