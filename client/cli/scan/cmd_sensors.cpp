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

// The camera and emitter figures the preset's returned light takes; empty when it has none.
std::string LightSummary(const v1::SensorPreset& preset) {
  const v1::ReturnedLight& l = preset.returned_light();
  if (l.full_well_e() <= 0 || l.read_noise_e() <= 0) return "";
  char line[320];
  std::snprintf(line, sizeof line,
                "light: exposure %g ms, full well %g e, read noise %g e (dynamic range %.1f dB), QE %g at %g nm, "
                "pupil %.3g mm, emitter %.3g W/sr",
                l.exposure_s() * 1e3, l.full_well_e(), l.read_noise_e(),
                20.0 * std::log10(l.full_well_e() / l.read_noise_e()), l.quantum_efficiency(),
                l.wavelength_m() * 1e9, l.aperture_diameter_m() * 1e3, l.emitter_w_per_sr());
  std::string text = line;
  if (l.modulation_frequency_hz() > 0) {
    std::snprintf(line, sizeof line, ", modulated at %g MHz", l.modulation_frequency_hz() / 1e6);
    text += line;
  }
  return text;
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
        const std::string light = LightSummary(p);
        if (!light.empty()) {
          ctx.Print("    " + light);
          ctx.Print("    light source: " + p.returned_light_source());
        }
      }
    }
    return kExitOk;
  });
}

}  // namespace vscan::cli
