// `vscan dataset run|watch|cancel|download|list|delete|score`: dataset jobs, which fill, scan and write
// every scene of a plan file on the server (docs/DATASETS.md).

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>


#include "campaign/campaign_report.h"
#include "datasets/cmd_dataset_score.h"
#include "job/job_commands.h"
#include "job/job_watch.h"
#include "session/commands.h"
#include "vscan/v1/job.grpc.pb.h"

namespace vscan::cli {
namespace {

struct DatasetRunArgs {
  std::string plan_file;
  std::string resume_job_id;
  std::string out_dir;
  bool watch = false;
  bool validate = false;
};

StatusOr<v1::StartDatasetResponse> StartDataset(client::Client& client, const v1::StartDatasetRequest& request) {
  auto stub = v1::JobService::NewStub(client.channel());
  grpc::ClientContext context;
  client.PrepareContext(&context, std::chrono::seconds(120));
  v1::StartDatasetResponse response;
  const grpc::Status status = stub->StartDataset(&context, request, &response);
  if (!status.ok()) return Status(static_cast<StatusCode>(status.error_code()), status.error_message());
  return response;
}

// Uploads each mesh file the server reads in the plan (relative paths from the plan's directory)
// and maps its path to the mesh: the plan is read by the server alone.
int UploadMeshes(Context& ctx, client::Client& client, const DatasetRunArgs& args, v1::DatasetSpec* spec) {
  v1::StartDatasetRequest listing;
  listing.set_list_mesh_files(true);
  listing.mutable_spec()->set_plan_yaml(spec->plan_yaml());
  const auto files = StartDataset(client, listing);
  if (!files.ok()) return ctx.ServerError(files.status());
  const std::filesystem::path plan_dir = std::filesystem::path(args.plan_file).parent_path();
  for (const v1::PlanMeshFile& named : files->mesh_files()) {
    client::MeshUploadOptions options;
    options.unit = named.unit();
    const std::filesystem::path file = plan_dir / named.path();  // an absolute path replaces plan_dir
    const auto mesh = client.UploadMeshFile(file.string(), options);
    if (!mesh.ok()) return ctx.ServerError(mesh.status());
    (*spec->mutable_mesh_ids())[named.path()] = mesh->mesh_id();
    ctx.Say("uploaded " + file.string() + " as mesh " + mesh->mesh_id());
  }
  return kExitOk;
}


// Writes the files of a ustar archive under dir (regular files only, the layout's relative paths).
Status ExtractTar(std::string_view tar, const std::filesystem::path& dir) {
  size_t at = 0;
  while (at + 512 <= tar.size()) {
    const char* header = tar.data() + at;
    if (header[0] == '\0') return Status::Ok();
    const std::string name(header, strnlen(header, 100));
    const uint64_t size = std::strtoull(std::string(header + 124, 12).c_str(), nullptr, 8);
    at += 512;
    if (name.empty() || name.find("..") != std::string::npos || name.front() == '/' || at + size > tar.size()) {
      return DataLoss("dataset.tar: a damaged or unsafe entry '" + name + "'");
    }
    const std::filesystem::path path = dir / name;
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(tar.data() + at, static_cast<std::streamsize>(size));
    if (!out) return Internal("cannot write " + path.string());
    at += (size + 511) / 512 * 512;
  }
  return Status::Ok();
}

int Download(Context& ctx, const std::string& job_id, const std::string& dir) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto job = client->GetJob(job_id);
  if (!job.ok()) return ctx.ServerError(job.status());
  for (const v1::Artifact& artifact : job->artifacts()) {
    if (artifact.name() != "dataset.tar") continue;
    std::string tar;
    const auto read = client->ReadArtifact(job_id, artifact.artifact_id(), [&](std::string_view bytes) {
      tar.append(bytes);
      return Status::Ok();
    });
    if (!read.ok()) return ctx.ServerError(read.status());
    if (const Status extracted = ExtractTar(tar, dir); !extracted.ok()) return ctx.LocalError(extracted);
    ctx.Done("dataset of job " + job_id + " in " + dir, dir);
    return kExitOk;
  }
  return ctx.ServerError(FailedPrecondition("job " + job_id + " has no dataset.tar (" +
                                            JobStateName(job->state()) + ": " + job->message() + ")"));
}

// The end of a followed dataset job: its state, then its tar extracted into out_dir when it
// succeeded (the artifacts are one tar, so FollowJob downloads nothing itself).
JobFinish DatasetFinish(Context& ctx, const std::string& out_dir) {
  return [&ctx, out_dir](const WatchResult& watched, const std::string&, const std::vector<std::string>&, double) {
    const v1::Job& job = watched.job;
    if (ctx.json()) ctx.EmitJson("{\"job\":" + ToJson(job) + "}");
    ctx.Say("job " + job.job_id() + " " + JobStateName(job.state()) +
            (job.message().empty() ? "" : "; " + job.message()));
    if (!out_dir.empty() && job.state() == v1::JOB_STATE_SUCCEEDED) {
      if (const int rc = Download(ctx, job.job_id(), out_dir); rc != kExitOk) return rc;
    }
    return JobExitCode(job.state());
  };
}

int Follow(Context& ctx, const std::string& job_id, const std::string& out_dir) {
  return FollowJob(ctx, job_id, "", JobClock::now(), DatasetFinish(ctx, out_dir));
}

int Run(Context& ctx, const DatasetRunArgs& args) {
  std::ifstream in(args.plan_file, std::ios::binary);
  if (!in) return ctx.UsageError("PLAN: cannot read '" + args.plan_file + "'");
  std::ostringstream text;
  text << in.rdbuf();
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  v1::StartDatasetRequest request;
  request.mutable_spec()->set_plan_yaml(text.str());
  request.mutable_spec()->set_resume_job_id(args.resume_job_id);
  request.set_validate_only(args.validate);
  if (const int rc = UploadMeshes(ctx, *client, args, request.mutable_spec()); rc != kExitOk) return rc;
  const auto started = StartDataset(*client, request);
  if (!started.ok()) return ctx.ServerError(started.status());
  if (args.validate) {
    ctx.Done("the server accepts this dataset plan", "");
    return kExitOk;
  }
  const v1::Job& job = started->job();
  const std::string line =
      "started dataset job " + job.job_id() + " of " + std::to_string(job.steps_total()) + " scenes";
  if (SayStarted(ctx, job, line, "", !args.watch && args.out_dir.empty())) return kExitOk;
  return Follow(ctx, job.job_id(), args.out_dir);
}

void AddDatasetRun(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<DatasetRunArgs>();
  auto* cmd = group.add_subcommand("run", "Start a dataset job from a plan file (its mesh files are uploaded)");
  cmd->add_option("PLAN", args->plan_file, "Plan file (YAML, docs/DATASETS.md)")->required();
  cmd->add_option("--resume", args->resume_job_id,
                  "Continue the directory of this ended dataset job, keeping the scenes it finished");
  cmd->add_flag("--watch", args->watch, "Follow the job until it ends");
  cmd->add_option("-o,--out", args->out_dir, "Follow the job, then download the dataset into this directory");
  cmd->add_flag("--validate", args->validate, "Ask the server to check the plan; start nothing");
  OnRun(cmd, ctx, [&ctx, args] { return Run(ctx, *args); });
}

void AddDatasetWatch(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("watch", "Follow a dataset job until it ends; exit 0 if it succeeded");
  auto id = std::make_shared<std::string>();
  auto out_dir = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  cmd->add_option("-o,--out", *out_dir, "Download the dataset into this directory when it succeeds");
  OnRun(cmd, ctx, [&ctx, id, out_dir] { return Follow(ctx, *id, *out_dir); });
}

void AddDatasetDownload(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("download", "Write a finished dataset job's dataset into a directory");
  auto id = std::make_shared<std::string>();
  auto dir = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  cmd->add_option("DIR", *dir, "Directory (created if needed)")->required();
  OnRun(cmd, ctx, [&ctx, id, dir] { return Download(ctx, *id, *dir); });
}

}  // namespace

void AddDatasetCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("dataset", "Dataset jobs: bins filled, scanned and written with ground truth");
  group->require_subcommand(1);
  AddDatasetRun(*group, ctx);
  AddDatasetWatch(*group, ctx);
  AddJobCancel(*group, ctx, "Cancel a dataset job (finished scenes stay; --resume continues them)");
  AddJobList(*group, ctx, "dataset", "List dataset jobs");
  AddJobDelete(*group, ctx, "Delete an ended dataset job and its artifacts from the server");
  AddDatasetDownload(*group, ctx);
  AddDatasetScore(*group, ctx);
}

}  // namespace vscan::cli
