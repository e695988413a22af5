#pragma once
// Campaign records for model jobs, read from the job catalogue: the campaign spec's scene, mount and
// returned light, and each scan artifact's commanded sensor pose (ScanArtifactInfo), decoded from
// their wire bytes.

#include "service/model/campaign_records.h"
#include "store/job_catalogue.h"

namespace vscan::api {

class CatalogueCampaignRecords final : public service::CampaignRecords {
 public:
  // limits: the server's, under which the campaign's sensor was accepted.
  CatalogueCampaignRecords(store::JobCatalogue& catalogue, const service::Limits& limits)
      : catalogue_(catalogue), limits_(limits) {}
  StatusOr<service::CampaignRecord> Get(const std::string& job_id) override;

 private:
  store::JobCatalogue& catalogue_;
  const service::Limits& limits_;
};

}  // namespace vscan::api
