#include "limit_options.h"

namespace vscan {

void AddLimitOptions(CLI::App& app, service::Limits& limits, LimitFlagsMib& mib) {
  mib.upload = limits.max_upload_bytes >> 20;
  mib.robot_bundle = limits.max_robot_bundle_bytes >> 20;
  mib.request_memory = limits.max_request_memory_bytes >> 20;
  mib.job = limits.max_job_bytes >> 20;
  mib.data = limits.max_data_bytes >> 20;
  app.add_option("--max-upload-mib", mib.upload, "Largest upload (mesh, robot bundle, cloud)")
      ->capture_default_str()->check(CLI::Range(1, 65536));
  app.add_option("--max-robot-bundle-mib", mib.robot_bundle, "Largest robot bundle (file bytes plus paths)")
      ->capture_default_str()->check(CLI::Range(1, 65536));
  app.add_option("--max-robot-files", limits.max_robot_files, "Most files in one robot bundle")
      ->capture_default_str()->check(CLI::Range(1, 1 << 20));
  app.add_option("--max-cloud-points", limits.max_cloud_points, "Most points in one uploaded cloud")
      ->capture_default_str()->check(CLI::Range(uint64_t{1}, uint64_t{1} << 34));
  app.add_option("--max-rays", limits.max_rays_per_scan, "Most rays one scan may cast")
      ->capture_default_str()->check(CLI::Range(1, 1 << 28));
  app.add_option("--max-request-memory-mib", mib.request_memory,
                 "Most memory one request (a scan, a campaign's scans, a dataset's frames, an upload, a model job) "
                 "may need by its estimate")
      ->capture_default_str()->check(CLI::Range(1, 1 << 22));
  app.add_option("--max-concurrent-scans", limits.max_concurrent_scans, "Scans running at once")
      ->capture_default_str()->check(CLI::Range(1, 1024));
  app.add_option("--max-queued-jobs", limits.max_queued_jobs, "Jobs that may wait for a free job slot")
      ->capture_default_str()->check(CLI::Range(1, 10000));
  app.add_option("--max-job-artifacts", limits.max_job_artifacts, "Most artifacts one job may store")
      ->capture_default_str()->check(CLI::Range(1, 100'000'000));
  app.add_option("--max-job-mib", mib.job, "Most bytes one job's artifacts may hold")
      ->capture_default_str()->check(CLI::Range(1, 1 << 30));
  app.add_option("--max-data-mib", mib.data,
                 "Most bytes the data directory may hold (blobs, dataset directories and catalogue); 0: as much as "
                 "the disk takes")
      ->envname("VSCAN_MAX_DATA_MIB")->capture_default_str()->check(CLI::Range(0, 1 << 30));
  // Six-digit scene directories cap a plan at 1,000,000 scenes whatever the flag says.
  app.add_option("--max-dataset-scenes", limits.max_dataset_scenes,
                 "Most scenes (seeds x bins x sensors) of one dataset job's plan")
      ->capture_default_str()->check(CLI::Range(1, 1'000'000));
}

void ApplyLimitFlags(const LimitFlagsMib& mib, service::Limits& limits) {
  limits.max_upload_bytes = mib.upload << 20;
  limits.max_robot_bundle_bytes = mib.robot_bundle << 20;
  limits.max_request_memory_bytes = mib.request_memory << 20;
  limits.max_job_bytes = mib.job << 20;
  limits.max_data_bytes = mib.data << 20;
}

}  // namespace vscan
