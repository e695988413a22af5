#pragma once
// Serves the read-only web view over HTTP or HTTPS (civetweb): the page at /, three.js and its orbit
// controls under /three/ (from Debian's libjs-three), and the API under /api/ (web_api.h).

#include <memory>
#include <string>

#include "vscan/common/status.h"
#include "web/web_api.h"

namespace vscan::web {

struct WebViewOptions {
  // HOST:PORT with a numeric IPv4 host (port 0 picks a free one).
  std::string address;
  // Debian's libjs-three: build/three.module.js and examples/jsm/controls/OrbitControls.js are served.
  std::string three_dir = "/usr/share/javascript/three";
  WebApiOptions api;
  // PEM files, as gRPC takes them: HTTPS when cert and key are set; client certificates are then
  // required when client_ca is set too.
  std::string tls_cert_file;
  std::string tls_key_file;
  std::string tls_client_ca_file;
};

class WebView {
 public:
  // The sources must outlive the view. UNAVAILABLE when the address cannot be bound or three.js
  // cannot be read.
  static StatusOr<std::unique_ptr<WebView>> Start(const WebViewOptions& options, const WebSources& sources);
  ~WebView();
  WebView(const WebView&) = delete;
  WebView& operator=(const WebView&) = delete;

  int port() const { return port_; }
  // Stops serving; waits for requests in progress.
  void Stop();

  struct Server;

 private:
  WebView(std::unique_ptr<Server> server, int port);
  std::unique_ptr<Server> server_;
  int port_ = 0;
};

}  // namespace vscan::web
