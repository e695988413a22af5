#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "session/args.h"
#include "session/commands.h"
#include "session/text_format.h"
#include "vscan/render/cloud_colours.h"
#include "vscan/render/png_io.h"
#include "vscan/render/render_input.h"
#include "vscan/render/renderer.h"

namespace vscan::cli {
namespace {

constexpr uint32_t kMaxSide = 16384;
constexpr float kMaxPointSize = 256;

struct RenderArgs {
  std::string input;
  std::string output;
  std::optional<std::string> color;
  std::string eye, target, up = "0,0,1";
  uint32_t width = 1024;
  uint32_t height = 768;
  float point_size = 2.0f;
  std::string background = "255,255,255";
};

Eigen::Vector3f ToFloat(const Eigen::Vector3d& v) { return v.cast<float>(); }

// Checks that need no file: a usage error message, or nothing.
std::optional<std::string> CheckArgs(const RenderArgs& args) {
  if (LowerExtension(args.output) != ".png") return "-o: output must end in .png";
  const std::string ext = LowerExtension(args.input);
  if (ext != ".ply" && ext != ".pcd" && ext != ".obj" && ext != ".stl") {
    return "INPUT: " + args.input + ": unknown extension '" + ext + "' (use .ply, .pcd, .obj or .stl)";
  }
  if (args.width == 0 || args.width > kMaxSide) return "--width: must be 1.." + std::to_string(kMaxSide);
  if (args.height == 0 || args.height > kMaxSide) return "--height: must be 1.." + std::to_string(kMaxSide);
  if (!(args.point_size >= 1 && args.point_size <= kMaxPointSize)) {
    return "--point-size: must be 1.." + Fixed(kMaxPointSize, 0) + " pixels";
  }
  return std::nullopt;
}

StatusOr<std::array<uint8_t, 3>> ParseBackground(const std::string& text) {
  ASSIGN_OR_RETURN(const std::vector<double> values, ParseNumbers(text, 3, "--background"));
  std::array<uint8_t, 3> rgb{};
  for (size_t i = 0; i < 3; ++i) {
    if (values[i] < 0 || values[i] > 255 || values[i] != static_cast<int>(values[i])) {
      return InvalidArgument("--background: each of r,g,b must be an integer 0..255");
    }
    rgb[i] = static_cast<uint8_t>(values[i]);
  }
  return rgb;
}

// --eye fixes the camera (looking at --target, else the box centre); without it the view fits the box.
StatusOr<render::View> ResolveView(const RenderArgs& args, const render::Bounds& bounds) {
  ASSIGN_OR_RETURN(const Eigen::Vector3d up, ParseVector3(args.up, "--up"));
  if (up.norm() < 1e-9) return InvalidArgument("--up: must not be zero");
  std::optional<Eigen::Vector3f> target;
  if (!args.target.empty()) {
    ASSIGN_OR_RETURN(const Eigen::Vector3d t, ParseVector3(args.target, "--target"));
    target = ToFloat(t);
  }
  if (args.eye.empty()) {
    return render::FitView(bounds, ToFloat(up), target, static_cast<float>(args.width) / args.height);
  }
  ASSIGN_OR_RETURN(const Eigen::Vector3d eye, ParseVector3(args.eye, "--eye"));
  render::View view;
  view.eye = ToFloat(eye);
  view.target = target.value_or(bounds.Centre());
  view.up = ToFloat(up);
  if ((view.target - view.eye).norm() < 1e-9f) return InvalidArgument("--eye: must differ from the target");
  return view;
}

// A failure of the renderer itself (no EGL, GL errors): exit 1.
int RenderError(Context& ctx, const Status& status) {
  const char* code = StatusCodeName(status.code());
  std::cerr << "error: " << code << ": " << status.message() << '\n';
  if (ctx.json()) {
    ctx.EmitJson(std::string("{\"error\":{\"code\":") + JsonQuote(code) + ",\"message\":" +
                 JsonQuote(status.message()) + "}}");
  }
  return 1;
}

int RunRender(Context& ctx, const RenderArgs& args) {
  if (const auto problem = CheckArgs(args)) return ctx.UsageError(*problem);
  const auto background = ParseBackground(args.background);
  if (!background.ok()) return ctx.UsageError(background.status().message());
  std::optional<render::ColourMode> mode;
  if (args.color) {
    auto parsed = render::ParseColourMode(*args.color);
    if (!parsed.ok()) return ctx.UsageError(parsed.status().message());
    mode = *parsed;
  }
  std::filesystem::path dir = std::filesystem::path(args.output).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    return ctx.LocalError(NotFound(args.output + ": directory " + dir.string() + " does not exist"));
  }

  const auto input = render::LoadRenderInput(args.input);
  if (!input.ok()) return ctx.LocalError(input.status());
  const bool is_cloud = input->kind == render::InputKind::kCloud;
  if (!is_cloud && mode) {
    return ctx.UsageError("--color: " + args.input + " is a mesh, drawn shaded; colour maps apply to clouds");
  }
  const auto view = ResolveView(args, input->bounds);
  if (!view.ok()) return ctx.UsageError(view.status().message());

  render::RenderOptions options;
  options.width = args.width;
  options.height = args.height;
  options.point_size = args.point_size;
  options.background = *background;
  const auto start = std::chrono::steady_clock::now();
  StatusOr<render::Image> image = Internal("not rendered");
  if (is_cloud) {
    const auto colours = render::CloudColours(input->cloud, mode.value_or(render::ColourMode::kDepth), *view);
    if (!colours.ok()) return ctx.UsageError(colours.status().message());
    image = render::RenderCloud(input->cloud, *colours, input->bounds, *view, options);
  } else {
    image = render::RenderMesh(input->mesh, input->bounds, *view, options);
  }
  const double render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!image.ok()) {
    if (image.status().code() == StatusCode::kInvalidArgument) return ctx.UsageError(image.status().message());
    return RenderError(ctx, image.status());
  }
  const Status written = render::WritePng(*image, args.output);
  if (!written.ok()) return ctx.LocalError(written);

  const std::string count_name = is_cloud ? "points" : "triangles";
  if (ctx.json()) {
    ctx.EmitJson("{\"output\":" + JsonQuote(args.output) + ",\"width\":" + std::to_string(args.width) +
                 ",\"height\":" + std::to_string(args.height) + ",\"" + count_name +
                 "\":" + std::to_string(input->Count()) + ",\"renderMs\":" + Fixed(render_ms, 3) + "}");
  } else {
    ctx.Say("render: " + std::to_string(input->Count()) + " " + count_name + " at " + std::to_string(args.width) +
            "x" + std::to_string(args.height) + " in " + Fixed(render_ms, 1) + " ms");
    ctx.Done("wrote " + args.output, args.output);
  }
  return kExitOk;
}

}  // namespace

void AddRenderCommand(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Draw a point cloud or mesh file to a PNG (OpenGL, headless EGL)");
  cmd->add_option("INPUT", args->input, "Cloud (.ply, .pcd) or mesh (.ply with faces, .obj, .stl)")->required();
  cmd->add_option("-o,--output", args->output, "Output image, .png")->required();
  cmd->add_option("--color", args->color,
                  "Cloud colouring: depth (default), intensity, instance, normal, height or status; meshes are shaded grey");
  cmd->add_option("--eye", args->eye, "Camera position x,y,z (default: fit the bounds from an oblique view)");
  cmd->add_option("--target", args->target, "Point the camera looks at x,y,z (default: the bounds' centre)");
  cmd->add_option("--up", args->up, "Up direction x,y,z; also the axis of --color height")->capture_default_str();
  cmd->add_option("--width", args->width, "Image width in pixels")->capture_default_str();
  cmd->add_option("--height", args->height, "Image height in pixels")->capture_default_str();
  cmd->add_option("--point-size", args->point_size, "Splat diameter in pixels")->capture_default_str();
  cmd->add_option("--background", args->background, "Background colour r,g,b, each 0..255")->capture_default_str();
  OnRun(cmd, ctx, [&ctx, args] { return RunRender(ctx, *args); });
}

}  // namespace vscan::cli
