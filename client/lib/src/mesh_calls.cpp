// Client's mesh calls: uploads, get, list, delete.

#include <filesystem>

#include "byte_streams.h"
#include "paging.h"
#include "unary_call.h"

namespace vscan::client {
namespace {

using SceneStub = v1::SceneService::Stub;

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
  if (options.material) *header->mutable_material() = *options.material;
  RETURN_IF_ERROR(SendChunks(context, *writer, message, size, options.chunk_bytes, read, progress, "mesh"));
  return std::move(*response.mutable_mesh());
}

StatusOr<v1::Mesh> Client::UploadMeshFile(const std::string& path, MeshUploadOptions options,
                                          const ProgressFn& progress) {
  uint64_t size = 0;
  ASSIGN_OR_RETURN(const ChunkSource source, FileSource(path, &size));
  if (options.format == v1::MESH_FORMAT_UNSPECIFIED) options.format = MeshFormatFromPath(path);
  if (options.format == v1::MESH_FORMAT_UNSPECIFIED) {
    return InvalidArgument(path + ": cannot tell the mesh format from the extension (use ply, obj or stl)");
  }
  if (options.name.empty()) options.name = std::filesystem::path(path).filename().string();
  return Upload(options, size, source, progress);
}

StatusOr<v1::Mesh> Client::UploadMeshBytes(std::string_view bytes, const MeshUploadOptions& options,
                                           const ProgressFn& progress) {
  return Upload(options, bytes.size(), BytesSource(bytes), progress);
}

StatusOr<v1::Mesh> Client::GetMesh(const std::string& mesh_id) {
  v1::GetMeshRequest request;
  request.set_mesh_id(mesh_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *scenes_, &SceneStub::GetMesh, request));
  return std::move(*response.mutable_mesh());
}

StatusOr<std::vector<v1::Mesh>> Client::ListMeshes() {
  return CollectPages<v1::Mesh>(
      [this](const std::string& token) {
        v1::ListMeshesRequest request;
        request.set_page_token(token);
        return UnaryCall(*this, *scenes_, &SceneStub::ListMeshes, request);
      },
      [](const v1::ListMeshesResponse& page) -> const auto& { return page.meshes(); });
}

Status Client::DeleteMesh(const std::string& mesh_id) {
  v1::DeleteMeshRequest request;
  request.set_mesh_id(mesh_id);
  return UnaryCall(*this, *scenes_, &SceneStub::DeleteMesh, request).status();
}

}  // namespace vscan::client
