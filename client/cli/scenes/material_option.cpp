#include "scenes/material_option.h"

#include <cstdio>
#include <cstdlib>
#include <map>

#include "session/commands.h"
#include "session/describe.h"

namespace vscan::cli {
namespace {

constexpr const char* kValuesForm = "albedo=A,metallic=M,roughness=R,specular=S";

StatusOr<double> ParseMaterialNumber(const std::string& key, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) {
    return InvalidArgument("--material: " + key + "='" + text + "' is not a number");
  }
  return value;
}

}  // namespace

StatusOr<v1::Material> ParseMaterialOption(const std::string& text) {
  v1::Material material;
  if (text.empty()) {
    return InvalidArgument("--material: empty; give a preset (vscan materials) or " + std::string(kValuesForm));
  }
  if (text.find('=') == std::string::npos) {
    material.set_preset(text);
    return material;
  }
  std::map<std::string, double> values;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string part = text.substr(start, comma - start);
    const size_t eq = part.find('=');
    if (eq == std::string::npos) return InvalidArgument("--material: '" + part + "' is not key=value");
    const std::string key = part.substr(0, eq);
    if (key != "albedo" && key != "metallic" && key != "roughness" && key != "specular") {
      return InvalidArgument("--material: unknown key '" + key + "' (expected " + kValuesForm + ")");
    }
    if (values.contains(key)) return InvalidArgument("--material: " + key + " given twice");
    ASSIGN_OR_RETURN(values[key], ParseMaterialNumber(key, part.substr(eq + 1)));
    start = comma + 1;
  }
  if (values.size() != 4) return InvalidArgument(std::string("--material: give all four of ") + kValuesForm);
  v1::MaterialValues* out = material.mutable_values();
  out->set_diffuse_albedo(values["albedo"]);
  out->set_metallic(values["metallic"]);
  out->set_roughness(values["roughness"]);
  out->set_specular_reflectance(values["specular"]);
  return material;
}

void AddMaterialsCommand(CLI::App& app, Context& ctx) {
  auto* cmd = app.add_subcommand("materials", "List the material presets meshes and objects can use (--material NAME)");
  auto verbose = std::make_shared<bool>(false);
  cmd->add_flag("-v,--verbose", *verbose, "Also print each preset's description");
  OnRun(cmd, ctx, [&ctx, verbose]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto presets = client->ListMaterialPresets();
    if (!presets.ok()) return ctx.ServerError(presets.status());
    if (ctx.json()) {
      v1::ListMaterialPresetsResponse all;
      for (const auto& p : *presets) *all.add_presets() = p;
      ctx.EmitJson(ToJson(all));
      return kExitOk;
    }
    for (const auto& p : *presets) {
      if (ctx.quiet()) {
        ctx.Print(p.name());
        continue;
      }
      const v1::MaterialValues& v = p.values();
      char line[256];
      std::snprintf(line, sizeof line, "%-26s albedo %.3g  metallic %.3g  roughness %.3g  specular %.3g",
                    p.name().c_str(), v.diffuse_albedo(), v.metallic(), v.roughness(), v.specular_reflectance());
      ctx.Print(line);
      if (*verbose) ctx.Print("    " + p.description());
    }
    return kExitOk;
  });
}

}  // namespace vscan::cli
