#include "api/reports/proto_report_writer.h"

#include "api/reports/report_convert.h"
#include "vscan/common/report_json.h"

namespace vscan::api {

std::string ProtoReportWriter::ModelJson(const service::ModelReport& report) const {
  return PrintReport(ModelReportMessage(report));
}

std::string ProtoReportWriter::CampaignJson(const std::string& job_id, const std::string& final_state,
                                            const service::CampaignPlan& plan,
                                            const std::vector<service::CampaignStepRecord>& steps) const {
  return PrintReport(CampaignReportMessage(job_id, final_state, plan, steps));
}

std::string ProtoReportWriter::BinFillJson(const service::BinFillPlan& plan,
                                           const service::BinFillReport& report) const {
  return PrintReport(BinReportMessage(plan, report));
}

std::string ProtoReportWriter::PickingJson(const service::PickingPlan& plan,
                                           const service::PickingJobReport& report) const {
  return PrintReport(PickingReportMessage(plan, report));
}

std::string ProtoReportWriter::PickingStepTruthJson(const service::PickingPlan& plan,
                                                    const service::StepView& view) const {
  return PrintReport(PickingStepTruthMessage(plan, view));
}

}  // namespace vscan::api
