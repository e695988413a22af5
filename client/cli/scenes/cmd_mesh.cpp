#include <cmath>

#include "scenes/material_option.h"
#include "session/args.h"
#include "session/commands.h"
#include "session/describe.h"
#include "session/uploads.h"

namespace vscan::cli {
namespace {

struct MeshUploadArgs {
  std::string file;
  std::string unit;
  double scale = 1.0;
  std::string name;
  std::string format;
  std::string material;
};

int RunMeshUpload(Context& ctx, const MeshUploadArgs& args) {
  client::MeshUploadOptions options;
  const auto unit = ParseUnit(args.unit);
  if (!unit.ok()) return ctx.UsageError(unit.status().message());
  options.unit = *unit;
  if (!(args.scale > 0) || !std::isfinite(args.scale)) return ctx.UsageError("--scale: must be a positive number");
  options.scale = args.scale;
  options.name = args.name;
  if (!args.format.empty()) {
    const auto format = ParseMeshFormat(args.format);
    if (!format.ok()) return ctx.UsageError(format.status().message());
    options.format = *format;
  } else {
    options.format = client::MeshFormatFromPath(args.file);
    if (options.format == v1::MESH_FORMAT_UNSPECIFIED) {
      return ctx.UsageError(args.file + ": cannot tell the format from the extension; pass --format ply|obj|stl");
    }
  }
  if (!args.material.empty()) {
    const auto material = ParseMaterialOption(args.material);
    if (!material.ok()) return ctx.UsageError(material.status().message());
    options.material = *material;
  }
  v1::Mesh mesh;
  if (const int rc = UploadMesh(ctx, args.file, options, &mesh); rc != kExitOk) return rc;
  if (ctx.json()) ctx.EmitJson(ToJson(mesh));
  ctx.Done("uploaded mesh " + Describe(mesh), mesh.mesh_id());
  return kExitOk;
}

void AddMeshUpload(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("upload", "Upload a PLY, OBJ or STL mesh");
  auto args = std::make_shared<MeshUploadArgs>();
  cmd->add_option("FILE", args->file, "Mesh file")->required();
  cmd->add_option("--unit", args->unit, "Unit the file is written in: m, cm, mm, in, ft")->required();
  cmd->add_option("--scale", args->scale, "Extra uniform scale after the unit conversion")->capture_default_str();
  cmd->add_option("--name", args->name, "Mesh name (default: the file name)");
  cmd->add_option("--format", args->format, "ply, obj or stl (default: from the extension)");
  cmd->add_option("--material", args->material,
                  "Default material of its objects: a preset (vscan materials) or "
                  "albedo=A,metallic=M,roughness=R,specular=S (default matte-grey)");
  OnRun(cmd, ctx, [&ctx, args] { return RunMeshUpload(ctx, *args); });
}

void AddMeshList(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("list", "List meshes");
  OnRun(cmd, ctx, [&ctx]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto meshes = client->ListMeshes();
    if (!meshes.ok()) return ctx.ServerError(meshes.status());
    if (ctx.json()) {
      v1::ListMeshesResponse all;
      for (const auto& m : *meshes) *all.add_meshes() = m;
      ctx.EmitJson(ToJson(all));
      return kExitOk;
    }
    for (const auto& m : *meshes) {
      ctx.Print(ctx.quiet() ? m.mesh_id() : Describe(m));
    }
    return kExitOk;
  });
}

void AddMeshGet(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("get", "Show a mesh");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ID", *id, "Mesh id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto mesh = client->GetMesh(*id);
    if (!mesh.ok()) return ctx.ServerError(mesh.status());
    if (ctx.json()) {
      ctx.EmitJson(ToJson(*mesh));
    } else {
      ctx.Print(Describe(*mesh) + "  sha256 " + mesh->sha256());
    }
    return kExitOk;
  });
}

void AddMeshDelete(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("delete", "Delete a mesh");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ID", *id, "Mesh id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const Status status = client->DeleteMesh(*id);
    if (!status.ok()) return ctx.ServerError(status);
    if (ctx.json()) ctx.EmitJson("{\"meshId\":" + JsonQuote(*id) + ",\"deleted\":true}");
    ctx.Done("deleted mesh " + *id, "");
    return kExitOk;
  });
}

}  // namespace

void AddMeshCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("mesh", "Upload, list, show and delete meshes");
  group->require_subcommand(1);
  AddMeshUpload(*group, ctx);
  AddMeshList(*group, ctx);
  AddMeshGet(*group, ctx);
  AddMeshDelete(*group, ctx);
  // Materials are set on meshes (and their objects), so the list of presets comes with them.
  AddMaterialsCommand(app, ctx);
}

}  // namespace vscan::cli
