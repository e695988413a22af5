#pragma once
// What a bin plan needs on the server before its fill starts: the scene (found by name or
// created) and the part and bin meshes (uploaded); and their removal when the fill cannot start.

#include <string>
#include <vector>

#include "bins/bin_plan.h"
#include "session/context.h"

namespace vscan::cli {

struct BinSetup {
  std::string scene_id;
  // The plan's spec with scene_id and every part's mesh_id filled in.
  v1::BinFillSpec spec;
  // What this run created, for UndoBinSetup.
  std::vector<std::string> created_meshes;
  std::string created_scene;
};

// Asks the server to check the plan (StartBinFill with validate_only) before anything is uploaded;
// 2 with the plan's file and line when the plan is at fault.
int CheckBinPlanOnServer(Context& ctx, const BinPlan& plan);

// Returns an exit code; *setup records what was created even on failure.
int SetUpBin(Context& ctx, const BinPlan& plan, BinSetup* setup);

void UndoBinSetup(Context& ctx, const BinSetup& setup);

// A failed call's error: a plan error (exit 2) when it names a value the plan set.
int ReportBinError(Context& ctx, const BinPlan& plan, const Status& status);

}  // namespace vscan::cli
