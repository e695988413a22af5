#include "dataset_oneshot.h"

#include <spdlog/spdlog.h>

#include "api/datasets/dataset_spec.h"
#include "service/datasets/dataset_job_shard.h"

namespace vscan {
namespace {

int ExitStatus(const Status& status) {
  if (status.ok()) return 0;
  spdlog::error("{}", status.ToString());
  return NamesAField(status.code()) ? 2 : 1;
}

}  // namespace

void AddDatasetOneShotOptions(CLI::App& app, DatasetOneShot& one_shot) {
  auto* shard = app.add_option("--dataset-shard", one_shot.shard_plan,
                               "Write one shard of this dataset plan into --out and exit (no server)");
  auto* merge = app.add_option("--dataset-merge", one_shot.merge_plan,
                               "Check that every shard of this plan is complete in --out, write its index and exit");
  shard->excludes(merge);
  app.add_option("--out", one_shot.out, "Dataset directory of --dataset-shard and --dataset-merge");
  app.add_option("--shard-index", one_shot.shard_index, "This shard, 0 .. shard count - 1 (JOB_COMPLETION_INDEX)")
      ->capture_default_str();
  app.add_option("--shard-count", one_shot.shard_count, "How many shards the seeds are dealt to")
      ->capture_default_str()->check(CLI::Range(1u, 1000000u));
}

std::optional<int> RunDatasetOneShot(const DatasetOneShot& one_shot) {
  if (one_shot.shard_plan.empty() && one_shot.merge_plan.empty()) return std::nullopt;
  if (one_shot.out.empty()) {
    spdlog::error("--out: the dataset directory is required");
    return 2;
  }
  if (!one_shot.merge_plan.empty()) {
    const Status merged = service::MergeDatasetFromFile(one_shot.merge_plan, one_shot.out);
    if (merged.ok()) spdlog::info("dataset {} is complete; scenes.json written", one_shot.out);
    return ExitStatus(merged);
  }
  const auto progress = [&](const service::dataset::DatasetProgress& p) {
    spdlog::info("shard {} of {}: {} of {} scenes done ({} found finished, {} written)", one_shot.shard_index,
                 one_shot.shard_count, p.done, p.total, p.skipped, p.written);
  };
  return ExitStatus(service::RunDatasetShardFromFile(one_shot.shard_plan, one_shot.out, one_shot.shard_index,
                                                     one_shot.shard_count, progress, api::DatasetReturnedLight)
                        .status());
}

}  // namespace vscan
