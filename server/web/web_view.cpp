#include "web/web_view.h"

#include <fstream>
#include <map>
#include <sstream>
#include <string_view>
#include <system_error>
#include <thread>

#include <civetweb.h>

#include "web/tls_front.h"
#include "web/web_assets.h"

namespace vscan::web {
namespace {

// The headers every answer carries; length < 0 sends none (a stream that ends when the connection does).
void SendHeaders(mg_connection* connection, int status, std::string_view content_type, long long length) {
  mg_response_header_start(connection, status);
  mg_response_header_add(connection, "Content-Type", content_type.data(), static_cast<int>(content_type.size()));
  if (length >= 0) mg_response_header_add(connection, "Content-Length", std::to_string(length).c_str(), -1);
  mg_response_header_add(connection, "Cache-Control", "no-store", -1);
  mg_response_header_add(connection, "X-Content-Type-Options", "nosniff", -1);
  // The page may load nothing but vscand's own files and API, and may not be framed by another site.
  mg_response_header_add(connection, "Content-Security-Policy",
                         "default-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
                         "frame-ancestors 'none'",
                         -1);
  mg_response_header_send(connection);
}

void Send(mg_connection* connection, int status, std::string_view content_type, std::string_view body, bool head) {
  SendHeaders(connection, status, content_type, static_cast<long long>(body.size()));
  if (!head) mg_write(connection, body.data(), body.size());
}

// The files of libjs-three the page imports, by the path the page asks for. OrbitControls imports
// "../../../build/three.module.js", which resolves to the first.
constexpr std::pair<const char*, const char*> kThreeFiles[] = {
    {"/three/build/three.module.js", "build/three.module.js"},
    {"/three/examples/jsm/controls/OrbitControls.js", "examples/jsm/controls/OrbitControls.js"},
};

void InitCivetweb() {
  static const unsigned features = mg_init_library(0);
  (void)features;
}

}  // namespace

struct WebView::Server {
  mg_context* context = nullptr;
  std::unique_ptr<WebApi> api;
  std::map<std::string, std::string, std::less<>> three_files;
  std::unique_ptr<TlsFront> tls;  // HTTPS: civetweb then listens on loopback behind it
};

namespace {

int ServeOnThisThread(mg_connection* connection, const WebView::Server& server) {
  const mg_request_info* request = mg_get_request_info(connection);
  const std::string_view method = request->request_method;
  const std::string_view path = request->local_uri ? request->local_uri : "";
  if (path.starts_with("/api/")) {
    const char* authorization = mg_get_header(connection, "Authorization");
    const WebReply reply =
        server.api->Handle(method, path, request->query_string ? request->query_string : "", authorization ? authorization : "");
    if (reply.stream) {
      SendHeaders(connection, reply.status, reply.content_type, reply.stream_length);
      reply.stream([connection](std::string_view bytes) {
        return mg_write(connection, bytes.data(), bytes.size()) == static_cast<int>(bytes.size());
      });
      return reply.status;
    }
    Send(connection, reply.status, reply.content_type, reply.body, false);
    return reply.status;
  }
  const bool head = method == "HEAD";
  if (method != "GET" && !head) {
    Send(connection, 405, "text/plain; charset=utf-8", "the web view is read-only: only GET is served\n", false);
    return 405;
  }
  if (const auto three = server.three_files.find(path); three != server.three_files.end()) {
    Send(connection, 200, "text/javascript; charset=utf-8", three->second, head);
    return 200;
  }
  if (const WebAsset* asset = FindAsset(path == "/" ? "/index.html" : path)) {
    Send(connection, 200, asset->content_type, asset->body, head);
    return 200;
  }
  Send(connection, 404, "text/plain; charset=utf-8", "not found\n", head);
  return 404;
}

// civetweb's workers run on small stacks (Debian's build: about 100 KiB), too small for the API's
// handlers, which read blobs and parse meshes; each request runs on a thread with the usual stack.
int Serve(mg_connection* connection, void* server_ptr) {
  const auto& server = *static_cast<const WebView::Server*>(server_ptr);
  int status = 500;
  try {
    std::thread([&] { status = ServeOnThisThread(connection, server); }).join();
  } catch (const std::system_error&) {
    // No thread to be had (the process is at its limit): say so rather than let the exception out.
    Send(connection, 503, "text/plain; charset=utf-8", "the web view is out of threads; try again\n", false);
    return 503;
  }
  return status;
}

}  // namespace

WebView::WebView(std::unique_ptr<Server> server, int port) : server_(std::move(server)), port_(port) {}

WebView::~WebView() { Stop(); }

StatusOr<std::unique_ptr<WebView>> WebView::Start(const WebViewOptions& options, const WebSources& sources) {
  auto server = std::make_unique<Server>();
  for (const auto& [served, file] : kThreeFiles) {
    const std::string path = options.three_dir + "/" + file;
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in || text.str().empty()) {
      return Unavailable("--web-three-dir: cannot read '" + path + "' (Debian package libjs-three)");
    }
    server->three_files.emplace(served, text.str());
  }
  server->api = std::make_unique<WebApi>(sources, options.api);
  InitCivetweb();
  // No document root: only what Serve answers is served.
  // A thread per connection: enough threads, and a short wait on each read or write, that clients
  // which send half a request or stop reading hold a few threads for seconds, not the whole view.
  const bool tls = !options.tls_cert_file.empty() && !options.tls_key_file.empty();
  const std::string listening = tls ? "127.0.0.1:0" : options.address;
  const char* civet_options[] = {"listening_ports", listening.c_str(), "num_threads", "32",
                                 "request_timeout_ms", "5000", nullptr};
  mg_callbacks callbacks{};
  mg_init_data init{&callbacks, nullptr, civet_options};
  char error_text[256] = "";
  unsigned error_code = 0;
  mg_error_data error{&error_code, error_text, sizeof(error_text)};
  server->context = mg_start2(&init, &error);
  if (!server->context) {
    return Unavailable("--web-listen: cannot listen on '" + listening + "': " + error_text);
  }
  mg_set_request_handler(server->context, "/", Serve, server.get());
  mg_server_port ports[1]{};
  const int bound = mg_get_server_ports(server->context, 1, ports);
  int port = bound > 0 ? ports[0].port : 0;
  if (tls) {
    auto front = TlsFront::Start({.address = options.address,
                                  .cert_file = options.tls_cert_file,
                                  .key_file = options.tls_key_file,
                                  .client_ca_file = options.tls_client_ca_file,
                                  .backend_port = port});
    if (!front.ok()) {
      mg_stop(server->context);
      return front.status();
    }
    server->tls = std::move(front).value();
    port = server->tls->port();
  }
  return std::unique_ptr<WebView>(new WebView(std::move(server), port));
}

void WebView::Stop() {
  // Event streams follow jobs that may run for hours: end them so that mg_stop need not wait.
  if (server_ && server_->context) server_->api->StopStreams();
  if (server_ && server_->tls) server_->tls->Stop();
  if (server_ && server_->context) {
    mg_stop(server_->context);
    server_->context = nullptr;
  }
}

}  // namespace vscan::web
