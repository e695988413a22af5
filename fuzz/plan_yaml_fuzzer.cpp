// libFuzzer target for the YAML plan readers: the first byte picks the reader, the rest is the
// plan. 0: a campaign plan (ParseCampaignPlan, `vscan campaign`), 1: a bin plan (ParseBinPlan,
// `vscan bin`), 2: a dataset plan (ParseDatasetPlanYaml, which vscand runs on a DatasetSpec's
// plan_yaml). Relative paths resolve against data/, so seeds can name real meshes and robots. A
// reader must refuse with INVALID_ARGUMENT (NOT_FOUND for a file the plan names), never throw or
// crash, and an accepted dataset plan must pass CheckPlan.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bins/bin_plan.h"
#include "campaign/campaign_plan.h"
#include "service/datasets/format/dataset_plan.h"
#include "service/datasets/format/dataset_plan_yaml.h"

namespace {

using vscan::Status;
using vscan::StatusCode;

void Check(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "plan_yaml_fuzzer: %s\n", what);
  std::abort();
}

void CheckRefusal(const Status& status, const char* reader) {
  if (status.ok() || status.code() == StatusCode::kInvalidArgument || status.code() == StatusCode::kNotFound) return;
  std::fprintf(stderr, "plan_yaml_fuzzer: %s refused with %s\n", reader, status.ToString().c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string yaml(reinterpret_cast<const char*>(data) + 1, size - 1);
  switch (data[0] % 3) {
    case 0:
      CheckRefusal(vscan::cli::ParseCampaignPlan(yaml, "plan.yaml", VSCAN_DATA_DIR).status(), "campaign plan");
      break;
    case 1:
      CheckRefusal(vscan::cli::ParseBinPlan(yaml, "bin.yaml", VSCAN_DATA_DIR).status(), "bin plan");
      break;
    default: {
      const auto plan = vscan::service::dataset::ParseDatasetPlanYaml(yaml, "plan");
      CheckRefusal(plan.status(), "dataset plan");
      if (plan.ok()) Check(vscan::service::dataset::CheckPlan(*plan).ok(), "accepted a dataset plan CheckPlan refuses");
      break;
    }
  }
  return 0;
}
