// vscand: the vscan server.

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <fstream>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>
#include <malloc.h>
#include <pthread.h>
#include <spdlog/spdlog.h>

#include "api/server/server.h"
#include "dataset_oneshot.h"
#include "limit_options.h"
#include "observability/log_format.h"
#include "observability/metrics_http.h"
#include "observability/server_metrics.h"
#include "vscan/common/logging.h"
#include "web/web_view.h"

namespace {

constexpr int kUsageError = 2;
constexpr int kForcedStop = 1;
// How long past the grace period cancelled calls may take to end before the process exits anyway.
constexpr double kStopSeconds = 5;

// Blocks SIGINT/SIGTERM in every thread so that only sigwait in main sees them.
sigset_t BlockStopSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  return set;
}

// Ends the process if the shutdown has not finished in time: work that ignores cancellation must not
// keep a stopping server alive, and the store is built to survive an abrupt end (kill -9) anyway.
class StopDeadline {
 public:
  explicit StopDeadline(double seconds) : thread_([this, seconds] { Watch(seconds); }) {}
  ~StopDeadline() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }

 private:
  void Watch(double seconds) {
    std::unique_lock lock(mutex_);
    if (wake_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return done_; })) return;
    spdlog::error("calls did not end within {:.1f} s of the stop signal; exiting without them", seconds);
    spdlog::default_logger()->flush();
    std::_Exit(kForcedStop);
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

// What a client can send in "authorization: Bearer <token>" (RFC 6750's b64token and more).
bool IsSendableToken(const std::string& token) {
  for (const unsigned char c : token) {
    if (c < 0x21 || c > 0x7e) return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  vscan::service::ServerOptions options;
  std::string log_level = "info";
  std::string log_format = "text";
  std::string metrics_listen;
  std::string token_file;
  vscan::web::WebViewOptions web;
  double grace_seconds = 10;

  CLI::App app{"vscand: the vscan scanning simulation server"};
  app.add_option("--listen", options.listen_address, "Address to listen on (host:port; port 0 picks one)")
      ->capture_default_str();
  app.add_option("--data-dir", options.data_dir, "Directory of the catalogue and blobs")->capture_default_str();
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")->capture_default_str();
  app.add_option("--log-format", log_format,
                 "text, or json: one object per line (time, level, logger, thread, message, request_id, fields)")
      ->capture_default_str()->check(CLI::IsMember({"text", "json"}));
  app.add_option("--metrics-listen", metrics_listen,
                 "Serve Prometheus metrics at http://HOST:PORT/metrics (numeric IPv4 host; off when not given)");
  app.add_option("--web-listen", web.address,
                 "Serve the read-only web view at http://HOST:PORT/ (numeric IPv4 host; off when not given; "
                 "the --token-file token guards its data; HTTPS with --tls-cert)");
  app.add_option("--web-three-dir", web.three_dir,
                 "Debian's libjs-three directory, whose three.js and orbit controls the web view's page loads")
      ->capture_default_str();
  app.add_option("--token-file", token_file, "Require 'authorization: Bearer <token>' with the token in this file");
  app.add_option("--tls-cert", options.tls_cert_file, "PEM certificate chain; enables TLS with --tls-key");
  app.add_option("--tls-key", options.tls_key_file, "PEM private key");
  app.add_option("--tls-client-ca", options.tls_client_ca_file, "PEM CA bundle; requires client certificates (mTLS)");
  app.add_option("--worker-threads", options.worker_threads, "Threads for scans and uploads off the gRPC threads")
      ->capture_default_str()->check(CLI::Range(1, 256));
  app.add_option("--call-threads", options.call_threads,
                 "Threads for blocking calls (inverse kinematics, catalogue writes) off the gRPC threads")
      ->capture_default_str()->check(CLI::Range(1, 256));
  vscan::LimitFlagsMib limit_mib;
  vscan::AddLimitOptions(app, options.limits, limit_mib);
  app.add_option("--max-concurrent-jobs", options.max_concurrent_jobs, "Jobs (scan campaigns) running at once")
      ->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--grace-seconds", grace_seconds,
                 "How long SIGTERM waits for running calls before it cancels them; work still running " +
                     std::to_string(static_cast<int>(kStopSeconds)) + " s later is abandoned (exit status 1)")
      ->capture_default_str()->check(CLI::Range(0.0, 86400.0));
  app.add_option("--stalled-reader-seconds", options.stalled_reader_seconds,
                 "A scan stream whose client has not read for this long is cancelled and its slot freed")
      ->capture_default_str()->check(CLI::Range(0.1, 86400.0));
  app.add_flag("--whole-cloud-scans", options.whole_cloud_scans,
               "Finish each ray-cast cloud before sending it instead of streaming rows as they are cast");
  app.add_option("--port-file", options.port_file, "Write the bound port to this file once listening");
  app.add_option("--mesh-importer", options.mesh_importer_path,
                 "The vscan-mesh-import helper that parses uploads (default: the one next to vscand)");
  app.add_option("--mesh-import-timeout", options.mesh_import_timeout_s, "Seconds one mesh upload may take to parse")
      ->capture_default_str()->check(CLI::Range(1, 86400));
  app.add_option("--mesh-import-memory-mib", options.mesh_import_memory_mib,
                 "Address space the mesh parser may use for one upload")
      ->capture_default_str()->check(CLI::Range(64, 1 << 20));
  app.add_option("--job-retention-hours", options.job_retention_hours,
                 "Delete ended jobs and their artifacts this many hours after they ended (0: keep forever)")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--job-retention-check-seconds", options.job_retention_check_s,
                 "How often job retention is applied (besides once at start)")
      ->capture_default_str()->check(CLI::Range(1, 86400));
  vscan::DatasetOneShot one_shot;
  vscan::AddDatasetOneShotOptions(app, one_shot);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return e.get_exit_code() == 0 ? app.exit(e) : (app.exit(e), kUsageError);
  }
  vscan::ApplyLimitFlags(limit_mib, options.limits);

  vscan::SetupLogging("vscand", log_level);
  vscan::observability::UseLogFormat(*vscan::observability::ParseLogFormat(log_format));
  if (const std::optional<int> exit_status = vscan::RunDatasetOneShot(one_shot)) return *exit_status;
  if (!token_file.empty()) {
    std::ifstream in(token_file);
    std::getline(in, options.token);
    // Files written on Windows or by hand end lines with "\r" or spaces that no client would send.
    options.token.erase(options.token.find_last_not_of(" \t\r") + 1);
    if (options.token.empty()) {
      spdlog::error("--token-file: '{}' is missing or empty", token_file);
      return kUsageError;
    }
    if (!IsSendableToken(options.token)) {
      spdlog::error("--token-file: the token may hold only visible ASCII characters (no spaces)");
      return kUsageError;
    }
  }

  // Scans hand out clouds of tens of MB; keeping freed memory mapped avoids page-faulting it in again.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  const sigset_t stop_signals = BlockStopSignals();
  // Up before the port file is written, so that a scrape after it finds the endpoint; stopped after
  // the server (destroyed after it). The job gauge joins the registry once the server starts.
  vscan::observability::Metrics();
  std::unique_ptr<vscan::observability::MetricsEndpoint> metrics;
  if (!metrics_listen.empty()) {
    auto endpoint = vscan::observability::MetricsEndpoint::Start(metrics_listen, vscan::observability::DefaultRegistry());
    if (!endpoint.ok()) {
      spdlog::error("cannot start: {}", endpoint.status().ToString());
      return 1;
    }
    metrics = std::move(endpoint).value();
    spdlog::info("metrics served on http://{}/metrics (port {})", metrics_listen, metrics->port());
  }
  // With the web view, the port file is written once it serves too, so that the file means "ready".
  const std::string port_file = options.port_file;
  if (!web.address.empty()) options.port_file.clear();
  auto server = vscan::api::Server::Start(options);
  if (!server.ok()) {
    spdlog::error("cannot start: {}", server.status().ToString());
    return 1;
  }
  std::unique_ptr<vscan::web::WebView> web_view;
  if (!web.address.empty()) {
    web.api.token = options.token;
    web.tls_cert_file = options.tls_cert_file;
    web.tls_key_file = options.tls_key_file;
    web.tls_client_ca_file = options.tls_client_ca_file;
    vscan::api::Server& served = **server;
    const vscan::web::WebSources sources{&served.scene_registry(), &served.job_tracker(), &served.cloud_catalogue(),
                                         &served.blobs(), &served.robots(), &served.dataset_directories()};
    auto view = vscan::web::WebView::Start(web, sources);
    if (!view.ok()) {
      spdlog::error("cannot start: {}", view.status().ToString());
      return 1;
    }
    web_view = std::move(view).value();
    spdlog::info("web view served on {}://{}/ (port {}), bearer token {}",
                 web.tls_cert_file.empty() ? "http" : "https", web.address, web_view->port(),
                 options.token.empty() ? "not required" : "required");
    if (!port_file.empty()) {
      if (const vscan::Status written = vscan::api::WritePortFile(port_file, (*server)->port()); !written.ok()) {
        spdlog::error("cannot start: {}", written.ToString());
        return 1;
      }
    }
  }
  int signal = 0;
  sigwait(&stop_signals, &signal);
  spdlog::info("received {}", signal == SIGTERM ? "SIGTERM" : "SIGINT");
  StopDeadline stop_deadline(grace_seconds + kStopSeconds);
  if (web_view) web_view->Stop();
  (*server)->Shutdown(grace_seconds);
  return 0;
}
