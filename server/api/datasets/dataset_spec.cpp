#include "api/datasets/dataset_spec.h"

#include <spdlog/spdlog.h>

#include "api/scan/returned_light_request.h"
#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"
#include "service/datasets/format/dataset_plan_yaml.h"
#include "service/datasets/dataset_bounds.h"
#include "service/datasets/dataset_directories.h"
#include "service/datasets/dataset_job_frames.h"
#include "service/scan/request_memory.h"
#include "service/job/job_kind.h"

namespace vscan::api {
namespace {

constexpr std::string_view kDatasetKind = service::JobKindName(service::JobKind::kDataset);

constexpr size_t kMaxPlanBytes = 1u << 20;

service::DatasetMeshLoader StoredMeshes(const v1::DatasetSpec& spec, service::ServiceContext& context) {
  return [&spec, &context](const service::dataset::DatasetPart& part,
                           const std::string& field) -> StatusOr<TriangleMesh> {
    std::string mesh_id = part.mesh_id;
    std::string id_field = "spec.plan_yaml." + field + ".mesh_id";
    if (mesh_id.empty()) {
      const auto found = spec.mesh_ids().find(part.mesh_file);
      if (found == spec.mesh_ids().end()) {
        return InvalidArgument("spec.mesh_ids", "no stored mesh for '" + part.mesh_file + "' (" + field +
                                                    ".mesh); upload the file and map its path to the mesh id");
      }
      mesh_id = found->second;
      id_field = "spec.mesh_ids[" + part.mesh_file + "]";
    }
    const StatusOr<std::shared_ptr<const TriangleMesh>> mesh = context.registry.LoadMesh(mesh_id);
    if (!mesh.ok() && mesh.status().code() == StatusCode::kNotFound) {
      return NotFound(id_field, "no mesh '" + mesh_id + "'");
    }
    RETURN_IF_ERROR(mesh.status());
    return **mesh;
  };
}

// "plan: bins[0].name: ..." and "plan:7: bins[0].parts[1].count: ..." read as fields of plan_yaml:
// "bins[0].parts[1].count: ... (line 7)".
std::string AsPlanField(const std::string& text) {
  if (!text.starts_with("plan:")) return text;
  const size_t digits = text.find_first_not_of("0123456789", 5);
  if (digits == 5 && text.compare(5, 1, " ") == 0) return text.substr(6);
  if (digits == std::string::npos || digits == 5 || text.compare(digits, 2, ": ") != 0) return text;
  return text.substr(digits + 2) + " (line " + text.substr(5, digits - 5) + ")";
}

// The job whose directory a resumed job writes (the first of a chain of resumptions).
StatusOr<std::string> ResumedDirectory(const std::string& job_id, store::JobCatalogue& jobs) {
  RETURN_IF_ERROR(RequireId(job_id, "spec.resume_job_id"));
  const StatusOr<store::JobRecord> record = jobs.GetJob(job_id);
  if (!record.ok() && record.status().code() == StatusCode::kNotFound) {
    return NotFound("spec.resume_job_id", "no job '" + job_id + "'");
  }
  RETURN_IF_ERROR(record.status());
  if (record->kind != kDatasetKind) {
    return FailedPrecondition("spec.resume_job_id", "job '" + job_id + "' is a " + record->kind + " job");
  }
  if (record->state == store::JobState::kQueued || record->state == store::JobState::kRunning) {
    return FailedPrecondition("spec.resume_job_id", "job '" + job_id + "' has not ended; cancel it first");
  }
  v1::DatasetSpec earlier;
  if (!earlier.ParseFromString(record->spec)) return DataLoss("job '" + job_id + "' has an unreadable dataset spec");
  return earlier.resume_job_id().empty() ? job_id : earlier.resume_job_id();
}


StatusOr<service::dataset::DatasetPlan> ParsePlan(const v1::DatasetSpec& spec) {
  if (spec.plan_yaml().empty()) return InvalidArgument("spec.plan_yaml", "required: the plan file's text");
  if (spec.plan_yaml().size() > kMaxPlanBytes) return InvalidArgument("spec.plan_yaml", "longer than 1 MiB");
  StatusOr<service::dataset::DatasetPlan> plan = service::dataset::ParseDatasetPlanYaml(spec.plan_yaml(), "plan");
  if (!plan.ok()) return InvalidArgument("spec.plan_yaml", AsPlanField(plan.status().message()));
  return plan;
}

}  // namespace

StatusOr<capture::ReturnedLightSpec> DatasetReturnedLight(const plan::ReturnedLightPlan& plan,
                                                  const service::DatasetSensorSetup& sensor) {
  v1::ReturnedLight light;
  light.set_emitter_w_per_sr(plan.emitter_w_per_sr);
  light.set_emitter_half_angle_deg(plan.emitter_half_angle_deg);
  light.set_exposure_s(plan.exposure_s);
  light.set_aperture_diameter_m(plan.aperture_diameter_m);
  light.set_quantum_efficiency(plan.quantum_efficiency);
  light.set_wavelength_m(plan.wavelength_m);
  light.set_full_well_e(plan.full_well_e);
  light.set_read_noise_e(plan.read_noise_e);
  light.set_min_snr(plan.min_snr);
  light.set_reference_e(plan.reference_e);
  light.set_indirect_samples(static_cast<uint32_t>(plan.indirect_samples));
  light.set_indirect_stride_px(static_cast<uint32_t>(plan.indirect_stride_px));
  light.set_modulation_frequency_hz(plan.modulation_frequency_hz);
  light.set_interreflection_ratio(plan.interreflection_ratio);
  light.set_ambient_irradiance_w_per_m2(plan.ambient_irradiance_w_per_m2);
  return ReturnedLightFromProto(light, sensor.camera, sensor.measurement.structured_light,
                                sensor.modulation_frequency_hz, sensor.illumination);
}

StatusOr<std::vector<v1::PlanMeshFile>> PlanMeshFiles(const v1::DatasetSpec& spec) {
  ASSIGN_OR_RETURN(const service::dataset::DatasetPlan plan, ParsePlan(spec));
  std::vector<v1::PlanMeshFile> files;
  std::set<std::string> listed;
  for (const service::dataset::DatasetBinFill& fill : plan.bin_fills) {
    for (const service::dataset::DatasetPart& part : fill.parts) {
      if (part.mesh_file.empty() || !listed.insert(part.mesh_file).second) continue;
      v1::PlanMeshFile& file = files.emplace_back();
      file.set_path(part.mesh_file);
      file.set_unit(LengthUnitNamed(part.unit));
    }
  }
  return files;
}

StatusOr<ValidatedDataset> ValidateDataset(const v1::DatasetSpec& spec, service::ServiceContext& context,
                                           store::JobCatalogue& jobs) {
  StatusOr<service::dataset::DatasetPlan> plan = ParsePlan(spec);
  RETURN_IF_ERROR(plan.status());
  // Before any mesh is loaded: the count needs the plan alone.
  RETURN_IF_ERROR(service::CheckDatasetScenes(*plan, context.options.limits.max_dataset_scenes)
                      .WithFieldPrefix("spec.plan_yaml"));
  StatusOr<service::DatasetSetup> setup =
      service::PrepareDataset(*plan, StoredMeshes(spec, context), context.options.limits.max_rays_per_scan,
                              DatasetReturnedLight);
  if (!setup.ok()) {
    const Status& error = setup.status();
    return error.field().rfind("spec.", 0) == 0 ? error : error.WithFieldPrefix("spec.plan_yaml");
  }
  if (plan->picks) {
    const std::string& robot_id = plan->picks->robot_id;
    const auto chain = context.robots.Chain(robot_id);
    if (!chain.ok() && chain.status().code() == StatusCode::kNotFound) {
      return NotFound("spec.plan_yaml.picks.robot_id", "no robot '" + robot_id + "'");
    }
    RETURN_IF_ERROR(chain.status());
    RETURN_IF_ERROR(service::AddDatasetPicks(*setup, *chain).WithFieldPrefix("spec.plan_yaml"));
  }
  // Frames captured ahead (and a scene's views) are held at once, each with its whole cloud.
  for (size_t i = 0; i < setup->sensors.size(); ++i) {
    const uint64_t frame_bytes = service::ScanMemoryBytes(service::DatasetFramePlan(setup->sensors[i]), false);
    const size_t in_flight = service::dataset::FramesInFlight(service::DatasetFramesAhead(), plan->views.count);
    RETURN_IF_ERROR(service::CheckRequestMemory(frame_bytes * in_flight,
                                                context.options.limits,
                                                "spec.plan_yaml",
                                                "sensors[" + std::to_string(i) + "]: capturing its frames"));
  }
  ValidatedDataset validated;
  validated.spec = spec;
  if (!spec.resume_job_id().empty()) {
    ASSIGN_OR_RETURN(*validated.spec.mutable_resume_job_id(), ResumedDirectory(spec.resume_job_id(), jobs));
  }
  if (context.dataset_directories) {
    const service::DatasetBytes bytes = service::EstimateDatasetBytes(
        *setup, service::DatasetTarBound(context.options.limits.max_request_memory_bytes));
    const std::string what = "the plan's " + std::to_string(service::DatasetImageCount(*plan)) +
                             " images, models" + (bytes.tar > 0 ? " and dataset.tar" : "");
    const Status room = context.dataset_directories->CheckRoom(
        bytes.total(), validated.spec.resume_job_id(), what);
    if (!room.ok()) return ResourceExhausted("spec.plan_yaml", room.message());
  }
  validated.setup = std::make_shared<const service::DatasetSetup>(std::move(setup).value());
  return validated;
}

std::string DatasetDirectoryId(const v1::DatasetSpec& spec, const std::string& job_id) {
  return spec.resume_job_id().empty() ? job_id : spec.resume_job_id();
}

std::string DatasetDirectoryOf(const store::JobRecord& job) {
  if (job.kind != kDatasetKind) return "";
  v1::DatasetSpec spec;
  if (!spec.ParseFromString(job.spec)) return "";
  return DatasetDirectoryId(spec, job.job_id);
}

StatusOr<std::set<std::string>> NamedDatasetDirectories(store::JobCatalogue& jobs) {
  ASSIGN_OR_RETURN(const std::vector<store::JobRecord> datasets, jobs.ListJobsOfKind(std::string(kDatasetKind)));
  std::set<std::string> named;
  for (const store::JobRecord& job : datasets) {
    // An unreadable spec keeps the directory of its own id: nothing is removed on a guess.
    const std::string directory = DatasetDirectoryOf(job);
    named.insert(directory.empty() ? job.job_id : directory);
  }
  return named;
}

uint64_t RemoveDatasetDirectoryOf(const store::JobRecord& job, store::JobCatalogue& jobs,
                                  service::DatasetDirectories& directories) {
  const std::string directory = DatasetDirectoryOf(job);
  if (directory.empty()) return 0;
  StatusOr<std::filesystem::path> aside = std::filesystem::path();
  {
    auto names = directories.HoldNames();
    const StatusOr<std::set<std::string>> named = NamedDatasetDirectories(jobs);
    if (!named.ok()) {
      spdlog::error("job {}: dataset directory {} kept: {}", job.job_id, directory, named.status().ToString());
      return 0;
    }
    if (named->count(directory)) return 0;  // a resumption of it is still recorded
    aside = directories.MoveAside(directory);
  }
  // Files go outside the lock: a large dataset takes a while.
  const StatusOr<uint64_t> removed = aside.ok() ? directories.RemoveAside(*aside) : StatusOr<uint64_t>(aside.status());
  if (!removed.ok()) {
    spdlog::error("job {}: dataset directory {} kept: {}", job.job_id, directory, removed.status().ToString());
    return 0;
  }
  spdlog::info("job {}: dataset directory {} removed ({} bytes)", job.job_id, directory, *removed);
  return *removed;
}

std::filesystem::path DatasetRootOf(const v1::DatasetSpec& spec, const std::string& job_id,
                                    const service::ServerOptions& options) {
  return service::DatasetJobRoot(options.data_dir, DatasetDirectoryId(spec, job_id));
}

}  // namespace vscan::api
