#pragma once
// A client-perception picking job's directory (<data dir>/picking/<job id>/): the estimates sent
// for each step (step-NNN-estimates.json, reports.proto's PickingStepTruth: the pile the step saw
// and the estimates, world frame) and how many steps finished (steps-done), both flushed to disk
// before anyone is told, so a job resumed after a crash finds them.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "service/picking/picking_run.h"
#include "vscan/common/status.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::api {

class PickingEstimatesFiles {
 public:
  PickingEstimatesFiles(const std::filesystem::path& data_dir, const std::string& job_id);
  static std::filesystem::path DirectoryOf(const std::filesystem::path& data_dir, const std::string& job_id);

  // Replaces the step's file in one step.
  Status Write(const v1::PickingStepTruth& estimates) const;
  // nullopt when there is none or it does not parse.
  std::optional<v1::PickingStepTruth> Read(size_t step) const;
  // steps-done: the step after the last one that finished (0 when none did).
  size_t FirstStep() const;
  Status MarkDone(size_t step) const;

 private:
  std::filesystem::path dir_;
};

// The stored estimates of a step, when they were sent for the pile awaited sees (same parts) and
// name its part types; nullopt otherwise.
std::optional<std::vector<picking::Estimate>> StoredEstimatesFor(const v1::PickingStepTruth& stored,
                                                                 const service::AwaitedStep& awaited);

// The hooks a client-perception run uses, over files and inbox (both outlive the run).
service::ClientEstimates ClientEstimatesOver(std::shared_ptr<const PickingEstimatesFiles> files,
                                             service::EstimatesInbox& inbox);

}  // namespace vscan::api
