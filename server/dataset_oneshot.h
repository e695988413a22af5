#pragma once
// vscand without a server: one shard of a dataset plan, or the merge, then exit. What the pods of
// the Kubernetes Indexed Job run (deploy/k8s/, docs/DATASETS.md).

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace vscan {

struct DatasetOneShot {
  std::string shard_plan;  // --dataset-shard PLAN
  std::string merge_plan;  // --dataset-merge PLAN
  std::string out;
  uint32_t shard_index = 0;
  uint32_t shard_count = 1;
};

void AddDatasetOneShotOptions(CLI::App& app, DatasetOneShot& one_shot);

// The process's exit status when a one-shot run was asked for: 0 done, 2 for a plan or arguments
// that cannot work, 1 for any other failure. nullopt: serve as usual.
std::optional<int> RunDatasetOneShot(const DatasetOneShot& one_shot);

}  // namespace vscan
