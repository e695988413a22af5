#pragma once
// Builds what a campaign plan describes on the server: meshes, scene, objects, table, robot, mount;
// and removes it again when the run fails before its campaign starts.

#include <string>
#include <vector>

#include "campaign/campaign_errors.h"
#include "campaign/campaign_plan.h"
#include "session/context.h"

namespace vscan::cli {

struct CampaignSetup {
  std::string scene_id;
  std::string mount_id;
  // What this run created (not the plan's existing ids), for UndoCampaignSetup.
  std::vector<std::string> created_meshes;
  std::string created_scene;
  std::string created_robot;
  std::string created_mount;
};

// Asks the server to check the plan's campaign (StartCampaign with validate_only) and the material
// presets its objects name (ListMaterialPresets) before anything is uploaded. Returns an exit code: 2 with the plan's file and line when the plan is at fault.
int CheckPlanOnServer(Context& ctx, const CampaignPlan& plan);

// Uploads and places everything the plan names (or takes its existing ids); prints each step
// unless --json/--quiet. Returns an exit code; *setup records what was created even on failure.
int SetUpCampaign(Context& ctx, const CampaignPlan& plan, CampaignSetup* setup);

// Deletes what setup records as created (mount, robot, scene, meshes) and says so on stderr.
void UndoCampaignSetup(Context& ctx, const CampaignSetup& setup);

// Prints a failed call's error, as a plan error (exit 2) when it names a value the plan set.
int ReportCallError(Context& ctx, const CampaignPlan& plan, PlanCall call, const Status& status, size_t object = 0);

}  // namespace vscan::cli
