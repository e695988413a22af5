#pragma once
// HTTPS in front of the web view. Debian 12's civetweb cannot load OpenSSL 3 (it looks up
// SSL_get_peer_certificate, which OpenSSL 3 no longer exports), so vscand ends TLS itself and relays
// each connection's plaintext to civetweb on a loopback port.

#include <memory>
#include <string>

#include "vscan/common/status.h"

namespace vscan::web {

struct TlsFrontOptions {
  std::string address;  // HOST:PORT, numeric IPv4; port 0 picks one
  std::string cert_file;
  std::string key_file;
  std::string client_ca_file;  // when set, clients must present a certificate it signed
  int backend_port = 0;        // civetweb on 127.0.0.1
  int max_connections = 64;    // further connections are closed at once
  int handshake_timeout_ms = 5000;
  int idle_timeout_ms = 60000;  // a connection with no bytes either way for this long is closed
};

class TlsFront {
 public:
  // UNAVAILABLE naming the flag when the certificate, key or CA cannot be used or the address bound.
  static StatusOr<std::unique_ptr<TlsFront>> Start(const TlsFrontOptions& options);
  ~TlsFront();
  TlsFront(const TlsFront&) = delete;
  TlsFront& operator=(const TlsFront&) = delete;

  int port() const;
  // Stops accepting, closes every relayed connection and waits for their threads.
  void Stop();

  struct State;

 private:
  explicit TlsFront(std::shared_ptr<State> state);
  std::shared_ptr<State> state_;
};

}  // namespace vscan::web
