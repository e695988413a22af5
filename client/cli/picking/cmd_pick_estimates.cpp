#include "picking/cmd_pick_estimates.h"

#include <fstream>
#include <memory>
#include <sstream>

#include "session/commands.h"
#include "vscan/common/report_json.h"
#include "vscan/v1/job.pb.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::cli {
namespace {

struct PickEstimatesArgs {
  std::string job_id;
  uint32_t step = 0;
  std::string file;
  std::string frame = "world";
  bool from_parts = false;
};

// FILE holds a PickingStepTruth (step-NNN-truth.json's shape): its estimates are sent, or its
// true parts with --from-parts (a truth file replayed as a perfect localizer).
StatusOr<v1::SubmitPickingEstimatesRequest> ReadEstimatesRequest(const PickEstimatesArgs& args) {
  std::ifstream in(args.file, std::ios::binary);
  if (!in) return NotFound(args.file + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  v1::PickingStepTruth file;
  RETURN_IF_ERROR(ParseReport(text.str(), args.file, &file));
  v1::SubmitPickingEstimatesRequest request;
  request.set_job_id(args.job_id);
  request.set_step(args.step);
  const auto& poses = args.from_parts ? file.parts() : file.estimates();
  const std::string list = args.from_parts ? "parts" : "estimates";
  for (int i = 0; i < poses.size(); ++i) {
    const v1::PickingPose& pose = poses[i];
    if (pose.world_from_part_size() != 16) {
      return InvalidArgument(args.file + ": " + list + "[" + std::to_string(i) +
                             "].world_from_part: need 16 values (row-major 4 x 4)");
    }
    v1::PickingEstimate* estimate = request.add_estimates();
    estimate->set_part(pose.part());
    estimate->set_score(args.from_parts ? 1.0 : pose.score());
    v1::Matrix4* matrix = args.frame == "camera" ? estimate->mutable_camera_from_part()->mutable_matrix()
                                                 : estimate->mutable_world_from_part()->mutable_matrix();
    for (double value : pose.world_from_part()) matrix->add_values(value);
  }
  return request;
}

int SubmitEstimates(Context& ctx, const PickEstimatesArgs& args) {
  if (args.frame != "world" && args.frame != "camera") return ctx.UsageError("--frame: world or camera");
  const auto request = ReadEstimatesRequest(args);
  if (!request.ok()) return ctx.LocalError(request.status());
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto accepted = client->SubmitPickingEstimates(*request);
  if (!accepted.ok()) return ctx.ServerError(accepted.status());
  ctx.Done("job " + args.job_id + " step " + std::to_string(args.step) + ": " + std::to_string(*accepted) +
               " estimates stored",
           args.job_id);
  return kExitOk;
}

}  // namespace

void AddPickEstimates(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<PickEstimatesArgs>();
  auto* cmd = group.add_subcommand(
      "estimates", "Send your localizer's estimates for the step a picking job with --perception client awaits");
  cmd->add_option("JOB", args->job_id, "Job id")->required();
  cmd->add_option("--step", args->step, "The step the job awaits (vscan pick get JOB shows it)")->required();
  cmd->add_option("FILE", args->file,
                  "JSON shaped as step-NNN-truth.json: {\"estimates\": [{\"part\", \"score\", "
                  "\"world_from_part\": 16 values row-major}]}")
      ->required();
  cmd->add_option("--frame", args->frame, "The poses' frame: world (default) or camera (the scan's sensor frame)");
  cmd->add_flag("--from-parts", args->from_parts, "Send the file's true parts instead (replays a truth file)");
  OnRun(cmd, ctx, [&ctx, args] { return SubmitEstimates(ctx, *args); });
}

}  // namespace vscan::cli
