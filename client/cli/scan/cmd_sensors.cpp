#include <cmath>
#include <cstdio>
#include <numbers>

#include "session/commands.h"
#include "session/describe.h"

namespace vscan::cli {
namespace {

std::string Summary(const v1::SensorPreset& preset) {
  const auto& spec = preset.spec();
  const auto& p = spec.has_structured_light() ? spec.structured_light().camera() : spec.pinhole();
  const double hfov = 2.0 * std::atan(p.width() / (2.0 * p.intrinsics().fx())) * 180.0 / std::numbers::pi;
  char line[256];
  std::snprintf(line, sizeof line, "%-18s %5ux%-5u hfov %5.1f deg  range %.2f-%.2f m%s", preset.name().c_str(),
                p.width(), p.height(), hfov, p.near(), p.far(),
                spec.has_structured_light() ? "  structured light" : "");
  return line;
}

}  // namespace

void AddSensorsCommand(CLI::App& app, Context& ctx) {
  auto* cmd = app.add_subcommand("sensors", "List the sensor presets a scan can use (--preset NAME)");
  auto verbose = std::make_shared<bool>(false);
  cmd->add_flag("-v,--verbose", *verbose, "Also print each preset's description and sources");
  OnRun(cmd, ctx, [&ctx, verbose]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto presets = client->ListSensorPresets();
    if (!presets.ok()) return ctx.ServerError(presets.status());
    if (ctx.json()) {
      v1::ListSensorPresetsResponse all;
      for (const auto& p : *presets) *all.add_presets() = p;
      ctx.EmitJson(ToJson(all));
      return kExitOk;
    }
    for (const auto& p : *presets) {
      ctx.Print(ctx.quiet() ? p.name() : Summary(p));
      if (*verbose && !ctx.quiet()) {
        ctx.Print("    " + p.description());
        ctx.Print("    source: " + p.source());
      }
    }
    return kExitOk;
  });
}

}  // namespace vscan::cli
