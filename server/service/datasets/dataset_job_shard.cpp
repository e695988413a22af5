#include "service/datasets/dataset_job_shard.h"

#include <fstream>
#include <sstream>

#include "service/datasets/format/dataset_merge.h"
#include "service/datasets/format/dataset_plan_yaml.h"
#include "service/datasets/dataset_job_frames.h"
#include "service/context/server_options.h"

namespace vscan::service {

StatusOr<dataset::DatasetPlan> ReadDatasetPlanFile(const std::filesystem::path& plan_file) {
  std::ifstream in(plan_file, std::ios::binary);
  if (!in) return NotFound("plan", "cannot read " + plan_file.string());
  std::ostringstream text;
  text << in.rdbuf();
  return dataset::ParseDatasetPlanYaml(text.str(), plan_file.string());
}

StatusOr<dataset::DatasetProgress> RunDatasetShardFromFile(
    const std::filesystem::path& plan_file, const std::filesystem::path& root, uint32_t shard_index,
    uint32_t shard_count, const std::function<void(const dataset::DatasetProgress&)>& on_progress,
    const DatasetLightResolver& resolve_light) {
  RETURN_IF_ERROR(dataset::CheckShard(shard_index, shard_count));
  ASSIGN_OR_RETURN(const dataset::DatasetPlan plan, ReadDatasetPlanFile(plan_file));
  if (plan.picks) {
    return FailedPrecondition("picks", plan_file.string() +
                                           ": checking picks needs the server's stored robot (picks.robot_id); "
                                           "run this plan as a dataset job (vscan dataset) or remove picks");
  }
  ASSIGN_OR_RETURN(DatasetSetup setup,
                   PrepareDataset(plan, MeshFilesFrom(plan_file.parent_path()), Limits{}.max_rays_per_scan,
                                  resolve_light));
  auto shared = std::make_shared<const DatasetSetup>(std::move(setup));
  dataset::ShardRun run;
  run.shard_index = shard_index;
  run.shard_count = shard_count;
  run.on_progress = on_progress;
  run.frames_ahead = DatasetFramesAhead();
  return dataset::RunDatasetShard(root, plan, shared->parts, BinFrameSource(shared, nullptr), run);
}

Status MergeDatasetFromFile(const std::filesystem::path& plan_file, const std::filesystem::path& root) {
  ASSIGN_OR_RETURN(const dataset::DatasetPlan plan, ReadDatasetPlanFile(plan_file));
  return dataset::MergeDataset(root, plan);
}

}  // namespace vscan::service
