#include "api/server/server.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>

#include <unistd.h>

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server.h>
#include <grpcpp/server_builder.h>
#include <spdlog/spdlog.h>

#include "api/server/call_observer.h"
#include "grpc/health/v1/health.pb.h"
#include "api/server/callback_queue_ticker.h"
#include "api/clouds/cloud_service.h"
#include "api/localization/localization_service.h"
#include "api/picking/picking_service.h"
#include "api/picking/picking_estimates_files.h"
#include "guards/data_dir_lock.h"
#include "api/datasets/dataset_spec.h"
#include "api/job/job_service.h"
#include "api/job/job_tracker.h"
#include "api/robot/robot_service.h"
#include "api/scan/scan_service.h"
#include "api/scenes/scene_service.h"
#include "guards/stall_watchdog.h"
#include "jobs/job_runner.h"
#include "jobs/periodic_task.h"
#include "observability/server_metrics.h"
#include "physics/convex_decomposition.h"
#include "service/datasets/dataset_directories.h"
#include "store/blob_gc.h"
#include "store/cloud_catalogue.h"
#include "store/database.h"
#include "store/ids.h"
#include "store/job_catalogue.h"

namespace vscan::api {
namespace {

StatusOr<std::string> ReadFile(const std::string& path, const char* flag) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return InvalidArgument(std::string(flag) + ": cannot read '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

StatusOr<std::shared_ptr<grpc::ServerCredentials>> Credentials(const service::ServerOptions& options) {
  if (options.tls_cert_file.empty() != options.tls_key_file.empty()) {
    return InvalidArgument("--tls-cert and --tls-key go together");
  }
  // Otherwise a server meant to require client certificates would quietly serve plaintext.
  if (options.tls_cert_file.empty() && !options.tls_client_ca_file.empty()) {
    return InvalidArgument("--tls-client-ca needs --tls-cert and --tls-key");
  }
  if (options.tls_cert_file.empty()) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions ssl;
  ASSIGN_OR_RETURN(std::string cert, ReadFile(options.tls_cert_file, "--tls-cert"));
  ASSIGN_OR_RETURN(std::string key, ReadFile(options.tls_key_file, "--tls-key"));
  ssl.pem_key_cert_pairs.push_back({key, cert});
  if (!options.tls_client_ca_file.empty()) {
    ASSIGN_OR_RETURN(ssl.pem_root_certs, ReadFile(options.tls_client_ca_file, "--tls-client-ca"));
    ssl.client_certificate_request = GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY;
  }
  return grpc::SslServerCredentials(ssl);
}

// The helper named by --mesh-importer, or else the one installed next to this executable.
StatusOr<geometry::ImportSandbox> MeshImportSandbox(const service::ServerOptions& options) {
  geometry::ImportSandbox sandbox;
  sandbox.timeout = std::chrono::seconds(options.mesh_import_timeout_s);
  sandbox.memory_limit_bytes = options.mesh_import_memory_mib << 20;
  std::error_code ec;
  std::filesystem::path helper(options.mesh_importer_path);
  if (helper.empty()) {
    std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return Unavailable("--mesh-importer: cannot locate vscand's own executable: " + ec.message());
    helper = self.parent_path() / "vscan-mesh-import";
  }
  helper = std::filesystem::absolute(helper, ec);
  sandbox.helper_path = helper.string();
  if (ec || !std::filesystem::is_regular_file(helper, ec) || ::access(helper.c_str(), X_OK) != 0) {
    return Unavailable("--mesh-importer: '" + sandbox.helper_path + "' is not an executable file");
  }
  return sandbox;
}

// vscan-poisson, installed next to this executable (and the mesh importer).
StatusOr<std::string> PoissonHelper(const geometry::ImportSandbox& sandbox) {
  const std::filesystem::path helper = std::filesystem::path(sandbox.helper_path).parent_path() / "vscan-poisson";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(helper, ec) || ::access(helper.c_str(), X_OK) != 0) {
    std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::filesystem::path beside = self.parent_path() / "vscan-poisson";
    if (ec || !std::filesystem::is_regular_file(beside, ec) || ::access(beside.c_str(), X_OK) != 0) {
      return Unavailable("'" + beside.string() + "' is not an executable file (Poisson reconstruction runs there)");
    }
    return beside.string();
  }
  return helper.string();
}

// Blobs older than this that no row names are left by a crash between a row's deletion and its file's.
constexpr std::chrono::minutes kOrphanBlobAge{5};

void ApplyRetention(JobTracker& tracker, double retention_hours) {
  const auto max_age_ms = static_cast<int64_t>(retention_hours * 3600e3);
  const auto deleted = tracker.DeleteEndedBefore(store::NowMs() - max_age_ms);
  if (!deleted.ok()) {
    spdlog::warn("job retention: {}", deleted.status().ToString());
  } else if (*deleted > 0) {
    spdlog::info("job retention: deleted {} jobs that ended over {} h ago", *deleted, retention_hours);
  }
}

// The vscan_jobs gauge: the live jobs of every running server in the process (tests run several).
class JobsGauge {
 public:
  static JobsGauge& Instance() {
    static JobsGauge gauge;
    return gauge;
  }
  void Add(JobTracker* tracker) {
    std::lock_guard lock(mutex_);
    trackers_.insert(tracker);
  }
  void Remove(JobTracker* tracker) {
    std::lock_guard lock(mutex_);
    trackers_.erase(tracker);
  }

 private:
  JobsGauge() {
    observability::DefaultRegistry().AddGaugeCollector("vscan_jobs",
                                                       "Jobs not yet ended, by kind and state (queued, running)",
                                                       {"kind", "state"}, [this] { return Collect(); });
  }
  std::vector<observability::GaugeSample> Collect() {
    std::lock_guard lock(mutex_);
    std::map<std::vector<std::string>, double> counts;
    for (JobTracker* tracker : trackers_) {
      for (const auto& sample : tracker->CountLive()) counts[sample.label_values] += sample.value;
    }
    std::vector<observability::GaugeSample> samples;
    for (auto& [labels, value] : counts) samples.push_back({labels, value});
    return samples;
  }

  std::mutex mutex_;
  std::set<JobTracker*> trackers_;
};

}  // namespace

// Counts a server's jobs in the vscan_jobs gauge while it lives.
class JobsGaugeEntry {
 public:
  explicit JobsGaugeEntry(JobTracker& tracker) : tracker_(&tracker) { JobsGauge::Instance().Add(tracker_); }
  ~JobsGaugeEntry() { JobsGauge::Instance().Remove(tracker_); }
  JobsGaugeEntry(const JobsGaugeEntry&) = delete;
  JobsGaugeEntry& operator=(const JobsGaugeEntry&) = delete;

 private:
  JobTracker* tracker_;
};

struct Server::Impl {
  // First member, so that it is released last, after the store has closed.
  std::optional<guards::DataDirLock> data_dir_lock;
  service::ServerOptions options;
  std::shared_ptr<store::Database> database;
  std::unique_ptr<store::Catalogue> catalogue;
  std::unique_ptr<store::BlobStore> blobs;
  std::unique_ptr<scenes::SceneRegistry> registry;
  std::unique_ptr<store::RobotCatalogue> robot_catalogue;
  std::unique_ptr<robot_registry::RobotRegistry> robots;
  std::unique_ptr<store::CloudCatalogue> cloud_catalogue;
  service::RasterProvider raster;
  std::unique_ptr<jobs::WorkerPool> workers;
  std::unique_ptr<jobs::WorkerPool> call_workers;
  std::unique_ptr<guards::StallWatchdog> stalled_readers;
  std::unique_ptr<service::ServiceContext> context;
  std::unique_ptr<SceneService> scene_service;
  std::unique_ptr<ScanService> scan_service;
  std::unique_ptr<RobotService> robot_service;
  std::unique_ptr<CloudService> cloud_service;
  std::unique_ptr<LocalizationService> localization_service;
  std::unique_ptr<PickingService> picking_service;
  std::unique_ptr<service::DatasetDirectories> dataset_directories;
  std::unique_ptr<store::JobCatalogue> job_catalogue;
  std::unique_ptr<JobTracker> job_tracker;
  std::unique_ptr<jobs::JobRunner> job_runner;
  std::unique_ptr<JobService> job_service;
  std::unique_ptr<jobs::PeriodicTask> retention;
  std::unique_ptr<grpc::Server> server;
  std::unique_ptr<CallbackQueueTicker> ticker;
  std::unique_ptr<JobsGaugeEntry> jobs_gauge;
  int port = 0;
};

Server::Server(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Server::~Server() { Shutdown(0); }

int Server::port() const { return impl_->port; }

Status WritePortFile(const std::string& path, int port) {
  // Renamed into place, so that a reader never sees a partial file.
  const std::string tmp = path + ".tmp";
  std::ofstream(tmp) << port << "\n";
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Unavailable("--port-file: cannot write '" + path + "': " + ec.message());
  return Status::Ok();
}

scenes::SceneRegistry& Server::scene_registry() { return *impl_->registry; }
JobTracker& Server::job_tracker() { return *impl_->job_tracker; }
store::CloudCatalogue& Server::cloud_catalogue() { return *impl_->cloud_catalogue; }
store::BlobStore& Server::blobs() { return *impl_->blobs; }
robot_registry::RobotRegistry& Server::robots() { return *impl_->robots; }
service::DatasetDirectories& Server::dataset_directories() { return *impl_->dataset_directories; }

StatusOr<std::unique_ptr<Server>> Server::Start(const service::ServerOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  std::error_code ec;
  const std::filesystem::path data_dir(options.data_dir);
  std::filesystem::create_directories(data_dir, ec);
  if (ec) return Unavailable("--data-dir: cannot create '" + options.data_dir + "': " + ec.message());
  // Before anything in the directory is read or written: a second server would interrupt our jobs.
  ASSIGN_OR_RETURN(impl->data_dir_lock, guards::DataDirLock::Acquire(data_dir));

  ASSIGN_OR_RETURN(impl->database, store::Database::Open(data_dir / "catalogue.sqlite"));
  impl->catalogue = std::make_unique<store::Catalogue>(impl->database);
  impl->blobs = std::make_unique<store::BlobStore>(data_dir / "blobs");
  RETURN_IF_ERROR(impl->blobs->Open());
  std::shared_ptr<store::DataQuota> quota;
  if (options.limits.max_data_bytes > 0) {
    const std::filesystem::path db = data_dir / "catalogue.sqlite";
    quota = std::make_shared<store::DataQuota>(
        options.limits.max_data_bytes,
        std::vector<std::filesystem::path>{db, db.string() + "-wal", db.string() + "-shm"});
    RETURN_IF_ERROR(quota->CountExisting(data_dir / "blobs"));
    impl->blobs->UseQuota(quota);
  }
  // Convex decompositions of parts, kept so that no later fill or restart cuts them again.
  std::filesystem::create_directories(data_dir / "decompositions", ec);
  if (!ec) physics::SetDecompositionDirectory((data_dir / "decompositions").string());
  // Dataset directories are counted once the catalogue says which jobs name them (below).
  impl->dataset_directories = std::make_unique<service::DatasetDirectories>(data_dir, quota);
  // An orphan only costs disk space: a failed sweep does not stop the server.
  if (const auto swept = store::SweepOrphanBlobs(*impl->database, *impl->blobs, kOrphanBlobAge); !swept.ok()) {
    spdlog::warn("orphan blob sweep: {}", swept.status().ToString());
  } else if (swept->files > 0) {
    spdlog::info("removed {} orphan blob files ({} bytes)", swept->files, swept->bytes);
  }
  ASSIGN_OR_RETURN(geometry::ImportSandbox import_sandbox, MeshImportSandbox(options));
  ASSIGN_OR_RETURN(impl->options.poisson_helper_path, PoissonHelper(import_sandbox));
  spdlog::info("Poisson reconstruction runs in {}", impl->options.poisson_helper_path);
  spdlog::info("mesh uploads are parsed by {} (at most {} s, {} MiB)", import_sandbox.helper_path,
               options.mesh_import_timeout_s, options.mesh_import_memory_mib);
  impl->registry = std::make_unique<scenes::SceneRegistry>(*impl->catalogue, *impl->blobs,
                                                           options.scene_cache_entries, std::move(import_sandbox));
  impl->robot_catalogue = std::make_unique<store::RobotCatalogue>(impl->database);
  impl->robots = std::make_unique<robot_registry::RobotRegistry>(
      *impl->robot_catalogue, *impl->blobs,
      robot::BundleLimits{options.limits.max_robot_bundle_bytes, options.limits.max_robot_files});
  impl->workers = std::make_unique<jobs::WorkerPool>(std::max<uint32_t>(1, options.worker_threads));
  impl->call_workers = std::make_unique<jobs::WorkerPool>(std::max<uint32_t>(1, options.call_threads));
  impl->cloud_catalogue = std::make_unique<store::CloudCatalogue>(impl->database);
  impl->context = std::make_unique<service::ServiceContext>(*impl->registry, *impl->workers, *impl->call_workers,
                                                            impl->options, *impl->robots, impl->raster,
                                                            *impl->cloud_catalogue, *impl->blobs);
  const std::chrono::duration<double> stall_limit(options.stalled_reader_seconds);
  impl->stalled_readers =
      std::make_unique<guards::StallWatchdog>(std::chrono::duration_cast<guards::StallWatchdog::Clock::duration>(stall_limit));
  impl->scene_service = std::make_unique<SceneService>(*impl->context);
  impl->scan_service = std::make_unique<ScanService>(*impl->context, impl->stalled_readers.get());
  impl->robot_service = std::make_unique<RobotService>(*impl->context);
  impl->cloud_service = std::make_unique<CloudService>(*impl->context, impl->stalled_readers.get());
  impl->localization_service = std::make_unique<LocalizationService>(*impl->context, impl->stalled_readers.get());
  impl->picking_service = std::make_unique<PickingService>(*impl->context);
  impl->job_catalogue = std::make_unique<store::JobCatalogue>(impl->database);
  ASSIGN_OR_RETURN(const int interrupted, impl->job_catalogue->InterruptUnfinished("server stopped while the job ran"));
  if (interrupted > 0) spdlog::warn("{} jobs were left unfinished by the last run; marked INTERRUPTED", interrupted);
  // Directories of deleted dataset jobs (a stop between the catalogue's delete and the removal,
  // or a removal cut short) go before any job runs; the others are counted against the quota.
  ASSIGN_OR_RETURN(const std::set<std::string> named, NamedDatasetDirectories(*impl->job_catalogue));
  ASSIGN_OR_RETURN(const int swept, impl->dataset_directories->Reconcile(named));
  if (swept > 0) spdlog::info("removed {} dataset directories that no job names", swept);
  if (quota) spdlog::info("data directory holds {} of at most {} bytes", quota->used_bytes(), quota->max_bytes());
  impl->context->dataset_directories = impl->dataset_directories.get();
  // Scratch files of campaigns that an older vscand left when it stopped (scans are now encoded in memory).
  std::filesystem::remove_all(data_dir / "tmp", ec);
  impl->job_tracker = std::make_unique<JobTracker>(*impl->job_catalogue, *impl->blobs, options.limits.max_job_artifacts,
                                                   options.limits.max_job_bytes);
  impl->job_tracker->OnDeleted([catalogue = impl->job_catalogue.get(), directories = impl->dataset_directories.get(),
                                data_dir](const store::JobRecord& job) {
    std::error_code removed;
    std::filesystem::remove_all(PickingEstimatesFiles::DirectoryOf(data_dir, job.job_id), removed);
    return RemoveDatasetDirectoryOf(job, *catalogue, *directories);
  });
  impl->job_runner = std::make_unique<jobs::JobRunner>(std::max<uint32_t>(1, options.max_concurrent_jobs));
  impl->job_service = std::make_unique<JobService>(*impl->context, *impl->job_tracker, *impl->job_runner,
                                                   impl->stalled_readers.get());
  if (options.job_retention_hours > 0) {
    ApplyRetention(*impl->job_tracker, options.job_retention_hours);
    impl->retention = std::make_unique<jobs::PeriodicTask>(
        std::chrono::seconds(std::max<uint32_t>(1, options.job_retention_check_s)),
        [tracker = impl->job_tracker.get(), hours = options.job_retention_hours] { ApplyRetention(*tracker, hours); });
  }

  observability::Metrics();  // every family is in the registry before the first scrape
  impl->jobs_gauge = std::make_unique<JobsGaugeEntry>(*impl->job_tracker);

  ASSIGN_OR_RETURN(auto credentials, Credentials(options));
  grpc::EnableDefaultHealthCheckService(true);
  // Puts health.proto into the generated pool, so that reflection describes grpc.health.v1.Health
  // and generic tools (buf curl --list-methods) can list every service.
  (void)grpc::health::v1::HealthCheckRequest::descriptor();
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(options.listen_address, credentials, &impl->port);
  builder.RegisterService(impl->scene_service.get());
  builder.RegisterService(impl->scan_service.get());
  builder.RegisterService(impl->robot_service.get());
  builder.RegisterService(impl->job_service.get());
  builder.RegisterService(impl->cloud_service.get());
  builder.RegisterService(impl->localization_service.get());
  builder.RegisterService(impl->picking_service.get());
  builder.SetMaxReceiveMessageSize(4 << 20);
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(MakeCallObserverFactory());
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  impl->server = builder.BuildAndStart();
  if (!impl->server || impl->port == 0) {
    return Unavailable("--listen: cannot listen on '" + options.listen_address + "'");
  }
  impl->ticker = std::make_unique<CallbackQueueTicker>(*impl->server, std::chrono::milliseconds(250));
  if (!options.port_file.empty()) RETURN_IF_ERROR(WritePortFile(options.port_file, impl->port));
  spdlog::info("vscand listening on {} (port {}), data in {}", options.listen_address, impl->port,
               std::filesystem::absolute(data_dir).string());
  spdlog::info("transport {}, bearer token {}",
               options.tls_cert_file.empty()
                   ? "plaintext"
                   : (options.tls_client_ca_file.empty() ? "TLS" : "mutual TLS (client certificates required)"),
               options.token.empty() ? "not required" : "required (health checks exempt)");
  return std::unique_ptr<Server>(new Server(std::move(impl)));
}

void Server::Shutdown(double grace_seconds) {
  if (!impl_ || !impl_->server) return;
  spdlog::info("shutting down: draining calls for up to {:.1f} s", grace_seconds);
  const auto deadline = std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int64_t>(grace_seconds * 1000));
  // Jobs end first (INTERRUPTED, recorded), so that their watch streams end and the drain is quick.
  impl_->job_runner->Stop();
  if (impl_->retention) impl_->retention->Stop();
  impl_->ticker->Stop();
  // Past the deadline gRPC cancels the calls still running (their OnCancel) and waits for them to end.
  impl_->server->Shutdown(deadline);
  if (std::chrono::system_clock::now() >= deadline) spdlog::info("grace period over: running calls were cancelled");
  impl_->workers->Stop();
  impl_->call_workers->Stop();
  impl_->server->Wait();
  impl_->server.reset();
  impl_->stalled_readers->Stop();
  spdlog::info("stopped");
}

}  // namespace vscan::api
