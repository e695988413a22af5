#pragma once
// Prints the reports jobs leave (model.json, campaign.json, bin.json, picking.json) from the plain structs the
// runs fill. The schema is proto/vscan/v1/reports.proto, which this layer cannot see: vscand's api
// layer implements this (api/reports), so no key is spelt here. The types are declared only: each
// belongs to the service folder whose run fills it.

#include <string>
#include <vector>

namespace vscan::service {

struct ModelReport;
struct CampaignPlan;
struct CampaignStepRecord;
struct BinFillPlan;
struct BinFillReport;
struct PickingPlan;
struct PickingJobReport;
struct StepView;

class ReportWriter {
 public:
  virtual ~ReportWriter() = default;
  virtual std::string ModelJson(const ModelReport& report) const = 0;
  virtual std::string CampaignJson(const std::string& job_id, const std::string& final_state, const CampaignPlan& plan,
                                   const std::vector<CampaignStepRecord>& steps) const = 0;
  virtual std::string BinFillJson(const BinFillPlan& plan, const BinFillReport& report) const = 0;
  virtual std::string PickingJson(const PickingPlan& plan, const PickingJobReport& report) const = 0;
  virtual std::string PickingStepTruthJson(const PickingPlan& plan, const StepView& view) const = 0;
};

}  // namespace vscan::service
