#pragma once
// Each function adds one command group to the app; the chosen command's callback stores its
// work in Context::action.

#include "session/app_main.h"

namespace vscan::cli {

void AddHealthCommand(CLI::App& app, Context& ctx);
void AddSceneCommands(CLI::App& app, Context& ctx);
void AddMeshCommands(CLI::App& app, Context& ctx);
void AddObjectCommands(CLI::App& app, Context& ctx);
void AddTableCommand(CLI::App& app, Context& ctx);
void AddScanCommand(CLI::App& app, Context& ctx);
void AddRenderCommand(CLI::App& app, Context& ctx);
void AddRobotCommands(CLI::App& app, Context& ctx);
void AddCampaignCommands(CLI::App& app, Context& ctx);
void AddSensorsCommand(CLI::App& app, Context& ctx);
void AddCloudCommands(CLI::App& app, Context& ctx);
// `vscan bin fill|scan|...`: bin fills and scans of them with ground truth.
void AddBinCommands(CLI::App& app, Context& ctx);
// `vscan align|reconstruct|evaluate` and the `vscan model` group.
void AddModelCommands(CLI::App& app, Context& ctx);
// `localize` and `score` under group (cmd_localize.cpp).
void AddLocalizationCommands(CLI::App& group, Context& ctx);
// `vscan dataset run|watch|cancel|download|list|delete|score` (cmd_dataset.cpp, cmd_dataset_score.cpp).
void AddDatasetCommands(CLI::App& app, Context& ctx);
// `vscan grasps` and `vscan picks` (picking/cmd_picks.cpp).
void AddPickingCommands(CLI::App& app, Context& ctx);
// `vscan pick run|watch|resume|get|list|cancel|delete|artifacts`: picking jobs (picking/cmd_pick.cpp).
void AddPickCommands(CLI::App& app, Context& ctx);
// `vscan view [SCENE]`: the web view's address (cmd_view.cpp).
void AddViewCommand(CLI::App& app, Context& ctx);

}  // namespace vscan::cli
