#pragma once
// Campaign records for model jobs, read from the job catalogue: the campaign spec's scene and mount
// and each scan artifact's commanded sensor pose (ScanArtifactInfo), decoded from their wire bytes.

#include "service/model/campaign_records.h"
#include "store/job_catalogue.h"

namespace vscan::api {

class CatalogueCampaignRecords final : public service::CampaignRecords {
 public:
  explicit CatalogueCampaignRecords(store::JobCatalogue& catalogue) : catalogue_(catalogue) {}
  StatusOr<service::CampaignRecord> Get(const std::string& job_id) override;

 private:
  store::JobCatalogue& catalogue_;
};

}  // namespace vscan::api
