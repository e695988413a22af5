#pragma once
// Builds what a campaign plan describes on the server: meshes, scene, objects, table, robot, mount.

#include "campaign_plan.h"
#include "context.h"

namespace vscan::cli {

struct CampaignSetup {
  std::string scene_id;
  std::string mount_id;
};

// Uploads and places everything the plan names (or takes its existing ids); prints each step
// unless --json/--quiet. Returns an exit code; kExitOk fills *setup.
int SetUpCampaign(Context& ctx, const CampaignPlan& plan, CampaignSetup* setup);

}  // namespace vscan::cli
