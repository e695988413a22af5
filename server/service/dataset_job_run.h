#pragma once
// A dataset job on a job-runner thread: every scene of the plan into its directory under the
// server's data directory, skipping scenes a previous run of that directory finished, an event per
// scene, the merge check, then the dataset as a tar artifact. A cancelled or stopped job keeps the
// scenes it finished; a job that resumes the directory continues from them.

#include <filesystem>
#include <memory>
#include <string>

#include "jobs/job_runner.h"
#include "service/dataset_job_setup.h"
#include "service/job_events.h"

namespace vscan::service {

struct DatasetJob {
  std::shared_ptr<const DatasetSetup> setup;
  std::filesystem::path root;  // <data dir>/datasets/<id of the job that started the directory>
};

// Where dataset jobs write: <data_dir>/datasets/<job id>.
std::filesystem::path DatasetJobRoot(const std::string& data_dir, const std::string& directory_job_id);

void RunDatasetJob(JobRecorder& recorder, const std::string& job_id, const DatasetJob& job, jobs::JobControl& control);

}  // namespace vscan::service
