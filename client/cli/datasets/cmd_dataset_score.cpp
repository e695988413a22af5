#include "datasets/cmd_dataset_score.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "localization/score_gripper_args.h"
#include "session/commands.h"
#include "session/text_format.h"
#include "vscan/v1/job.grpc.pb.h"

namespace vscan::cli {
// Named, not anonymous: the unity build puts this file beside cmd_localize.cpp's `score`.
namespace dataset_score {

// The server's bound on results_csv: a larger file is refused here before it is sent.
constexpr uintmax_t kMaxResultsBytes = 3 << 20;

struct ScoreArgs {
  std::string job_id;
  std::string results;
  bool json = false;
  ScoreGripperArgs gripper;
};

std::string Recall(bool has, double value) { return has ? Fixed(value, 3) : "-"; }

// grasp: add the grasp success column.
std::string Row(const std::string& id, const std::string& middle, const v1::DatasetRecall& r, bool grasp) {
  char line[200];
  std::snprintf(line, sizeof(line), "%-7s %-18s %9llu %9llu %8s %8s", id.c_str(), middle.c_str(),
                static_cast<unsigned long long>(r.valid_instances()), static_cast<unsigned long long>(r.estimates()),
                Recall(r.has_add_recall(), r.add_recall()).c_str(),
                Recall(r.has_mssd_average_recall(), r.mssd_average_recall()).c_str());
  std::string row = line;
  if (grasp) {
    std::snprintf(line, sizeof(line), " %8s", Recall(r.has_grasp_success(), r.grasp_success()).c_str());
    row += line;
  }
  return row;
}

void PrintScore(Context& ctx, const std::string& job_id, const v1::ScoreDatasetResultsResponse& response, bool grasp) {
  ctx.Say("dataset of job " + job_id + ": " + std::to_string(response.scene_count()) + " scenes, " +
          std::to_string(response.image_count()) + " images, " + std::to_string(response.true_instances()) +
          " true instances; " + std::to_string(response.rows()) + " estimates read in " +
          Fixed(response.score_ms() / 1000, 2) + " s");
  if (response.ignored_rows() > 0) {
    std::string images;
    for (const std::string& image : response.ignored_images()) images += (images.empty() ? "" : ", ") + image;
    ctx.Say(std::to_string(response.ignored_rows()) + " estimates left out: their images are not in the dataset (" +
            images + (static_cast<uint64_t>(response.ignored_images_size()) < response.ignored_rows() ? ", ..." : "") +
            ")");
  }
  char header[200];
  const std::string grasp_column = grasp ? "    grasp" : "";
  std::snprintf(header, sizeof(header), "%-7s %-18s %9s %9s %8s %8s", "obj_id", "diameter   error", "valid",
                "estimates", "ADD(-S)", "MSSD AR");
  ctx.Say(header + grasp_column);
  for (const v1::DatasetObjectScore& object : response.objects()) {
    ctx.Say(Row(std::to_string(object.obj_id()),
                Fixed(object.diameter_mm(), 1) + " mm " + (object.uses_add_s() ? "ADD-S" : "ADD"), object.recall(), grasp));
  }
  ctx.Say(Row("all", "", response.overall(), grasp));
  std::snprintf(header, sizeof(header), "%-7s %-18s %9s %9s %8s %8s", "scene", "", "valid", "estimates", "ADD(-S)",
                "MSSD AR");
  ctx.Say(header + grasp_column);
  for (const v1::DatasetSceneScore& scene : response.scenes()) {
    ctx.Say(Row(std::to_string(scene.scene_id()), "", scene.recall(), grasp));
  }
  ctx.Say("ADD(-S) correct below " + Fixed(response.add_threshold() * 100, 0) +
          "% of the diameter, MSSD averaged over 5% to 50%; true instances seen less than " +
          Fixed(response.min_visible_fraction() * 100, 0) + "% are not counted");
  if (grasp) {
    ctx.Say("grasp: share of valid true instances whose estimate's best grasp from above holds the true part "
            "(unmatched instances count as failures)");
  }
}

int RunScore(Context& ctx, const ScoreArgs& args) {
  if (args.json) ctx.global.json = true;
  const auto gripper = BuildScoreGripper(args.gripper);
  if (!gripper.ok()) return ctx.UsageError(gripper.status().message());
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(args.results, ec);
  if (ec) return ctx.LocalError(NotFound("--results: cannot read '" + args.results + "': " + ec.message()));
  if (size > kMaxResultsBytes) {
    return ctx.UsageError("--results: " + std::to_string(size) + " bytes, more than the " +
                          std::to_string(kMaxResultsBytes >> 20) + " MiB the server takes in one call");
  }
  std::ifstream in(args.results, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) return ctx.LocalError(NotFound("--results: cannot read '" + args.results + "'"));
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  v1::ScoreDatasetResultsRequest request;
  request.set_job_id(args.job_id);
  request.set_results_csv(text.str());
  if (*gripper) *request.mutable_gripper() = **gripper;
  if (const auto up = ScoreUp(args.gripper)) *request.mutable_up() = *up;
  auto stub = v1::JobService::NewStub(client->channel());
  grpc::ClientContext context;
  const double seconds = ctx.global.timeout.value_or(600);
  client->PrepareContext(&context, std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000)));
  v1::ScoreDatasetResultsResponse response;
  const grpc::Status status = stub->ScoreDatasetResults(&context, request, &response);
  if (!status.ok()) return ctx.ServerError(Status(static_cast<StatusCode>(status.error_code()), status.error_message()));
  if (ctx.json()) {
    ctx.EmitJson(ToJson(response));
    return kExitOk;
  }
  PrintScore(ctx, args.job_id, response, gripper->has_value());
  return kExitOk;
}

}  // namespace dataset_score

void AddDatasetScore(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<dataset_score::ScoreArgs>();
  auto* cmd = group.add_subcommand(
      "score", "Score a BOP results CSV against a finished dataset job's ground truth (ADD(-S), MSSD; as bop_toolkit)");
  cmd->add_option("JOB", args->job_id, "Dataset job id")->required();
  cmd->add_option("--results", args->results,
                  "BOP results file: scene_id,im_id,obj_id,score,R,t,time (R row-major, t in mm)")
      ->required();
  cmd->add_flag("--json", args->json, "Print the ScoreDatasetResultsResponse as JSON");
  AddScoreGripperOptions(cmd, args->gripper);
  OnRun(cmd, ctx, [&ctx, args] { return dataset_score::RunScore(ctx, *args); });
}

}  // namespace vscan::cli
