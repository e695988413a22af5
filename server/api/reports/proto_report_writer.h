#pragma once
// The ReportWriter of vscand: each report through its message in proto/vscan/v1/reports.proto,
// printed by protobuf's JSON printer (vscan/common/report_json.h).

#include "service/job/report_writer.h"

namespace vscan::api {

class ProtoReportWriter final : public service::ReportWriter {
 public:
  std::string ModelJson(const service::ModelReport& report) const override;
  std::string CampaignJson(const std::string& job_id, const std::string& final_state, const service::CampaignPlan& plan,
                           const std::vector<service::CampaignStepRecord>& steps) const override;
  std::string BinFillJson(const service::BinFillPlan& plan, const service::BinFillReport& report) const override;
  std::string PickingJson(const service::PickingPlan& plan, const service::PickingJobReport& report) const override;
  std::string PickingStepTruthJson(const service::PickingPlan& plan, const service::StepView& view) const override;
};

}  // namespace vscan::api
