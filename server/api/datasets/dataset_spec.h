#pragma once
// A DatasetSpec checked and turned into a dataset job: the plan parsed and prepared (meshes
// loaded from the store, presets found), the directory chosen, and a resumed job looked up, so
// that a bad request creates no job. Errors name "spec.<field>", plan keys under
// "spec.plan_yaml".

#include <set>
#include <string>
#include <vector>

#include "service/datasets/dataset_job_run.h"
#include "service/context/service_context.h"
#include "store/job_catalogue.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

struct ValidatedDataset {
  std::shared_ptr<const service::DatasetSetup> setup;
  // The spec as the job records it: resume_job_id names the job whose directory it writes.
  v1::DatasetSpec spec;
};

// A dataset plan's returned_light for one sensor (service::DatasetLightResolver) as a ScanRequest's
// returned_light: the same defaults and checks.
StatusOr<capture::ReturnedLightSpec> DatasetReturnedLight(const plan::ReturnedLightPlan& light,
                                                          const service::DatasetSensorSetup& sensor);

StatusOr<ValidatedDataset> ValidateDataset(const v1::DatasetSpec& spec, service::ServiceContext& context,
                                           store::JobCatalogue& jobs);

// The mesh files spec.plan_yaml names (each once, in the plan's order, with its unit), for a client
// to upload before it starts the job; the plan is parsed, nothing else is checked.
StatusOr<std::vector<v1::PlanMeshFile>> PlanMeshFiles(const v1::DatasetSpec& spec);

// The id naming the directory a job with this (validated) spec writes: its own, or the resumed job's.
std::string DatasetDirectoryId(const v1::DatasetSpec& spec, const std::string& job_id);

// The directories the catalogue's dataset jobs write (DatasetDirectoryId of each).
StatusOr<std::set<std::string>> NamedDatasetDirectories(store::JobCatalogue& jobs);
// The directory a recorded dataset job writes; empty for another kind or an unreadable spec.
std::string DatasetDirectoryOf(const store::JobRecord& job);

// After job was deleted: removes its dataset directory when no recorded job names it any more
// (a failure is logged; the next start removes it). Returns the bytes removed.
uint64_t RemoveDatasetDirectoryOf(const store::JobRecord& job, store::JobCatalogue& jobs,
                                  service::DatasetDirectories& directories);

// The directory a job with this (validated) spec writes.
std::filesystem::path DatasetRootOf(const v1::DatasetSpec& spec, const std::string& job_id,
                                    const service::ServerOptions& options);

}  // namespace vscan::api
