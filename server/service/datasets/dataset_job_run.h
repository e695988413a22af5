#pragma once
// A dataset job on a job-runner thread: every scene of the plan into its directory under the
// server's data directory, skipping scenes a previous run of that directory finished, an event per
// scene, the merge check, then the dataset as a tar artifact. A cancelled or stopped job keeps the
// scenes it finished; a job that resumes the directory continues from them. With --max-data-mib
// the directory is measured between scenes: a next scene that would pass the bound ends the job
// FAILED (RESOURCE_EXHAUSTED naming the flag), its scenes kept for a resume once space is freed.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "jobs/job_runner.h"
#include "service/datasets/dataset_bounds.h"
#include "service/datasets/dataset_directories.h"
#include "service/datasets/dataset_job_setup.h"
#include "service/job/job_events.h"

namespace vscan::service {

struct DatasetJob {
  std::shared_ptr<const DatasetSetup> setup;
  std::filesystem::path root;  // <data dir>/datasets/<id of the job that started the directory>
  std::string directory_id;    // the id of the job that started the directory
  // Counts the directory against the data quota; null: not counted (tests).
  DatasetDirectories* directories = nullptr;
  // dataset.tar is made only for directories up to this size (DatasetTarBound).
  uint64_t max_tar_bytes = kMaxTarArtifactBytes;
};

// Where dataset jobs write: <data_dir>/datasets/<job id>.
std::filesystem::path DatasetJobRoot(const std::string& data_dir, const std::string& directory_job_id);

void RunDatasetJob(JobRecorder& recorder, const std::string& job_id, const DatasetJob& job, jobs::JobControl& control);

}  // namespace vscan::service
