// Writes the synthetic dataset (test::SyntheticPlan) into the directory given, in one process or
// as one shard: `vscan_dataset_fixture [--views] <root> [<shard index> <shard count>]`; "merge" as
// the second argument merges. --views writes test::SyntheticMultiViewPlan (three views a scene).

#include <cstdio>
#include <cstdlib>
#include <string>

#include "service/datasets/format/dataset_merge.h"
#include "service/datasets/format/dataset_run.h"
#include "synthetic_bin.h"

using namespace vscan;
using namespace vscan::service::dataset;

int main(int argc, char** argv) {
  const bool views = argc > 1 && std::string(argv[1]) == "--views";
  if (views) {
    ++argv;
    --argc;
  }
  if (argc != 2 && argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: %s [--views] <root> [<shard index> <shard count> | merge]\n", argv[0]);
    return 2;
  }
  const std::string root = argv[1];
  const DatasetPlan plan = views ? test::SyntheticMultiViewPlan() : test::SyntheticPlan();
  const FrameSource source = test::SyntheticSource(plan);
  Status status;
  if (argc == 2) {
    status = WriteDataset(root, plan, test::SyntheticParts(), source, nullptr).status();
  } else if (argc == 3 && std::string(argv[2]) == "merge") {
    status = MergeDataset(root, plan);
  } else if (argc == 4) {
    ShardRun run;
    run.shard_index = static_cast<uint32_t>(std::strtoul(argv[2], nullptr, 10));
    run.shard_count = static_cast<uint32_t>(std::strtoul(argv[3], nullptr, 10));
    status = RunDatasetShard(root, plan, test::SyntheticParts(), source, run).status();
  } else {
    std::fprintf(stderr, "unknown arguments\n");
    return 2;
  }
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.ToString().c_str());
    return 1;
  }
  return 0;
}
