#pragma once
// --material: a preset's name, or explicit values as albedo=A,metallic=M,roughness=R,specular=S.

#include <string>

#include "session/app_main.h"
#include "vscan/common/status.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::cli {

// The server checks names and ranges; this only splits the text (INVALID_ARGUMENT naming --material).
StatusOr<v1::Material> ParseMaterialOption(const std::string& text);

// `vscan materials`: the presets the server knows, with their values.
void AddMaterialsCommand(CLI::App& app, Context& ctx);

}  // namespace vscan::cli
