// vscan: command-line client for vscand.

#include "session/commands.h"

int main(int argc, char** argv) {
  vscan::cli::Context ctx;
  CLI::App app{"vscan: command-line client for the vscan 3D scanning simulator", "vscan"};
  app.set_version_flag("--version", VSCAN_VERSION);
  app.require_subcommand(1);
  app.fallthrough();
  vscan::cli::AddGlobalOptions(app, ctx.global);
  vscan::cli::AddHealthCommand(app, ctx);
  vscan::cli::AddSceneCommands(app, ctx);
  vscan::cli::AddMeshCommands(app, ctx);
  vscan::cli::AddObjectCommands(app, ctx);
  vscan::cli::AddTableCommand(app, ctx);
  vscan::cli::AddScanCommand(app, ctx);
  vscan::cli::AddRenderCommand(app, ctx);
  vscan::cli::AddRobotCommands(app, ctx);
  vscan::cli::AddCampaignCommands(app, ctx);
  vscan::cli::AddBinCommands(app, ctx);
  vscan::cli::AddCloudCommands(app, ctx);
  vscan::cli::AddModelCommands(app, ctx);
  vscan::cli::AddLocalizationCommands(app, ctx);
  vscan::cli::AddDatasetCommands(app, ctx);
  vscan::cli::AddPickingCommands(app, ctx);
  vscan::cli::AddPickCommands(app, ctx);
  vscan::cli::AddSensorsCommand(app, ctx);
  vscan::cli::AddViewCommand(app, ctx);
  return vscan::cli::ParseAndRun(app, ctx, argc, argv);
}
