#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "paging.h"
#include "unary_call.h"

namespace vscan::client {
namespace {

using Stub = v1::SceneService::Stub;

}  // namespace

StatusOr<v1::Mesh> Client::Upload(const MeshUploadOptions& options, uint64_t size,
                                  const std::function<StatusOr<size_t>(char*, size_t)>& read,
                                  const ProgressFn& progress) {
  if (options.format == v1::MESH_FORMAT_UNSPECIFIED) {
    return InvalidArgument("format: mesh format is required (ply, obj or stl)");
  }
  grpc::ClientContext context;
  PrepareContext(&context, options_.stream_timeout);
  v1::UploadMeshResponse response;
  auto writer = scenes_->UploadMesh(&context, &response);

  v1::UploadMeshRequest message;
  v1::MeshHeader* header = message.mutable_header();
  header->set_name(options.name);
  header->set_format(options.format);
  header->set_unit(options.unit);
  header->set_scale(options.scale);
  header->set_size_bytes(size);
  bool open = writer->Write(message);

  Status local;
  uint64_t sent = 0;
  std::string buffer(std::max<size_t>(options.chunk_bytes, 1), '\0');
  while (open && sent < size) {
    const size_t want = static_cast<size_t>(std::min<uint64_t>(buffer.size(), size - sent));
    auto got = read(buffer.data(), want);
    if (!got.ok() || *got == 0) {
      local = got.ok() ? DataLoss("mesh source ended after " + std::to_string(sent) + " of " +
                                  std::to_string(size) + " bytes")
                       : got.status();
      context.TryCancel();
      break;
    }
    message.set_chunk(buffer.data(), *got);
    open = writer->Write(message);
    sent += *got;
    if (open && progress) progress(sent, size);
  }
  if (open && local.ok()) writer->WritesDone();
  const grpc::Status status = writer->Finish();
  if (!local.ok()) return local;
  if (!status.ok()) return FromGrpc(status);
  return std::move(*response.mutable_mesh());
}

StatusOr<v1::Mesh> Client::UploadMeshFile(const std::string& path, MeshUploadOptions options,
                                          const ProgressFn& progress) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return NotFound(path + ": " + ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open: " + std::strerror(errno));
  if (options.format == v1::MESH_FORMAT_UNSPECIFIED) options.format = MeshFormatFromPath(path);
  if (options.format == v1::MESH_FORMAT_UNSPECIFIED) {
    return InvalidArgument(path + ": cannot tell the mesh format from the extension (use ply, obj or stl)");
  }
  if (options.name.empty()) options.name = std::filesystem::path(path).filename().string();
  return Upload(
      options, size,
      [&](char* buf, size_t n) -> StatusOr<size_t> {
        in.read(buf, static_cast<std::streamsize>(n));
        if (in.bad()) return DataLoss(path + ": read failed");
        return static_cast<size_t>(in.gcount());
      },
      progress);
}

StatusOr<v1::Mesh> Client::UploadMeshBytes(std::string_view bytes, const MeshUploadOptions& options,
                                           const ProgressFn& progress) {
  size_t offset = 0;
  return Upload(
      options, bytes.size(),
      [&](char* buf, size_t n) -> StatusOr<size_t> {
        const size_t take = std::min(n, bytes.size() - offset);
        std::memcpy(buf, bytes.data() + offset, take);
        offset += take;
        return take;
      },
      progress);
}

StatusOr<v1::Mesh> Client::GetMesh(const std::string& mesh_id) {
  v1::GetMeshRequest request;
  request.set_mesh_id(mesh_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *scenes_, &Stub::GetMesh, request));
  return std::move(*response.mutable_mesh());
}

StatusOr<std::vector<v1::Mesh>> Client::ListMeshes() {
  return CollectPages<v1::Mesh>(
      [this](const std::string& token) {
        v1::ListMeshesRequest request;
        request.set_page_token(token);
        return UnaryCall(*this, *scenes_, &Stub::ListMeshes, request);
      },
      [](const v1::ListMeshesResponse& page) -> const auto& { return page.meshes(); });
}

Status Client::DeleteMesh(const std::string& mesh_id) {
  v1::DeleteMeshRequest request;
  request.set_mesh_id(mesh_id);
  return UnaryCall(*this, *scenes_, &Stub::DeleteMesh, request).status();
}

}  // namespace vscan::client
