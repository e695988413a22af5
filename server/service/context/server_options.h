#pragma once
// Everything vscand is configured with: where it listens, where it keeps data, its bounds. Read by
// the service layer and the gRPC layer alike.

#include <cstdint>
#include <string>

namespace vscan::service {

struct Limits {
  uint64_t max_upload_bytes = 256ull << 20;
  uint64_t max_rays_per_scan = 16ull << 20;
  uint32_t max_concurrent_scans = 4;
  uint32_t max_page_size = 1000;
  // Jobs waiting for a runner slot; StartCampaign beyond it is RESOURCE_EXHAUSTED.
  uint32_t max_queued_jobs = 64;
  // A robot bundle's file bytes plus paths, and its file count.
  uint64_t max_robot_bundle_bytes = 64ull << 20;
  uint32_t max_robot_files = 1024;
  // Points of one uploaded cloud.
  uint64_t max_cloud_points = 20'000'000;
  // What one request may hold in memory at once, by the estimate of request_memory.h.
  uint64_t max_request_memory_bytes = 2048ull << 20;
  // Artifacts one job may store, and their bytes.
  uint32_t max_job_artifacts = 100'000;
  uint64_t max_job_bytes = 64ull << 30;
  // Bytes the data directory may hold (blobs, dataset directories, catalogue); 0: as much as the
  // disk takes.
  uint64_t max_data_bytes = 0;
  // Scenes (seeds x bins x sensors) of one dataset plan a job may write.
  uint64_t max_dataset_scenes = 100'000;
};

struct ServerOptions {
  std::string listen_address = "127.0.0.1:50051";
  std::string data_dir = "vscan-data";
  // Clients must send "authorization: Bearer <token>" when set.
  std::string token;
  // TLS when both are set; mutual TLS when client_ca is set too.
  std::string tls_cert_file;
  std::string tls_key_file;
  std::string tls_client_ca_file;
  // Written with the bound port once listening (useful with port 0).
  std::string port_file;
  // Scans and uploads.
  uint32_t worker_threads = 2;
  // Blocking unary calls (inverse kinematics with collision retries, catalogue writes), apart
  // from scans so that a long scan does not hold them up.
  uint32_t call_threads = 2;
  // Jobs (campaigns) running at once, each on its own runner thread.
  uint32_t max_concurrent_jobs = 1;
  uint32_t scene_cache_entries = 8;
  // The vscan-mesh-import helper that parses uploads; empty means the one next to vscand.
  std::string mesh_importer_path;
  // The vscan-poisson executable; empty solves Poisson inside the server (not cancellable).
  std::string poisson_helper_path;
  uint32_t mesh_import_timeout_s = 60;
  uint64_t mesh_import_memory_mib = 8192;
  // A Scan stream whose client has not read for this long is cancelled and its slot freed.
  double stalled_reader_seconds = 10;
  // Ended jobs are deleted (with their artifacts) this long after their last change; 0 keeps them.
  double job_retention_hours = 0;
  // How often retention is applied (besides once at start).
  uint32_t job_retention_check_s = 300;
  // Ray-cast scans finish the whole cloud before sending it, as the measured and raster scans
  // do, instead of streaming rows as they are cast (for comparisons).
  bool whole_cloud_scans = false;
  Limits limits;
};

}  // namespace vscan::service
