// Client's CloudService calls: uploads, get, list, delete and reads of stored clouds.

#include <filesystem>

#include "byte_streams.h"
#include "paging.h"
#include "unary_call.h"

namespace vscan::client {
namespace {

using CloudStub = v1::CloudService::Stub;

std::unique_ptr<CloudStub> NewCloudStub(const Client& client) { return v1::CloudService::NewStub(client.channel()); }

StatusOr<v1::Cloud> StreamCloud(const Client& client, const CloudUploadOptions& options, uint64_t size,
                           const ChunkSource& read, const ProgressFn& progress) {
  auto stub = NewCloudStub(client);
  grpc::ClientContext context;
  client.PrepareContext(&context, client.options().stream_timeout);
  v1::UploadCloudResponse response;
  auto writer = stub->UploadCloud(&context, &response);

  v1::UploadCloudRequest message;
  v1::CloudHeader* header = message.mutable_header();
  header->set_name(options.name);
  header->set_format(options.format);
  if (options.sensor_pose) *header->mutable_sensor_pose() = *options.sensor_pose;
  header->set_frame(options.frame);
  if (options.camera) *header->mutable_camera() = *options.camera;
  header->set_scene_id(options.scene_id);
  header->set_size_bytes(size);
  RETURN_IF_ERROR(SendChunks(context, *writer, message, size, options.chunk_bytes, read, progress, "cloud"));
  return std::move(*response.mutable_cloud());
}

}  // namespace

StatusOr<v1::Cloud> Client::UploadCloudFile(const std::string& path, CloudUploadOptions options,
                                            const ProgressFn& progress) {
  uint64_t size = 0;
  ASSIGN_OR_RETURN(const ChunkSource source, FileSource(path, &size));
  if (options.format == v1::CLOUD_FORMAT_UNSPECIFIED) options.format = CloudFormatFromPath(path);
  if (options.name.empty()) options.name = std::filesystem::path(path).filename().string();
  return StreamCloud(*this, options, size, source, progress);
}

StatusOr<v1::Cloud> Client::UploadCloudBytes(std::string_view bytes, const CloudUploadOptions& options,
                                             const ProgressFn& progress) {
  return StreamCloud(*this, options, bytes.size(), BytesSource(bytes), progress);
}

StatusOr<v1::Cloud> Client::GetCloud(const std::string& cloud_id) {
  auto stub = NewCloudStub(*this);
  v1::GetCloudRequest request;
  request.set_cloud_id(cloud_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &CloudStub::GetCloud, request));
  return std::move(*response.mutable_cloud());
}

StatusOr<std::vector<v1::Cloud>> Client::ListClouds(const std::string& job_id) {
  auto stub = NewCloudStub(*this);
  return CollectPages<v1::Cloud>(
      [this, &stub, &job_id](const std::string& token) {
        v1::ListCloudsRequest request;
        request.set_page_token(token);
        request.set_job_id(job_id);
        return UnaryCall(*this, *stub, &CloudStub::ListClouds, request);
      },
      [](const v1::ListCloudsResponse& page) -> const auto& { return page.clouds(); });
}

StatusOr<v1::DeleteCloudResponse> Client::DeleteCloud(const std::string& cloud_id) {
  auto stub = NewCloudStub(*this);
  v1::DeleteCloudRequest request;
  request.set_cloud_id(cloud_id);
  return UnaryCall(*this, *stub, &CloudStub::DeleteCloud, request);
}

StatusOr<v1::Cloud> Client::ReadCloud(const std::string& cloud_id, const ArtifactSink& sink,
                                      const ProgressFn& progress) {
  auto stub = NewCloudStub(*this);
  grpc::ClientContext context;
  PrepareContext(&context, options_.stream_timeout);
  v1::ReadCloudRequest request;
  request.set_cloud_id(cloud_id);
  auto reader = stub->ReadCloud(&context, request);
  return ReceiveChunks<v1::ReadCloudResponse, v1::Cloud>(
      context, *reader, [](const v1::ReadCloudResponse& r) { return r.cloud(); },
      [](const v1::Cloud& c) { return c.size_bytes(); }, sink, progress, "cloud '" + cloud_id + "'");
}

}  // namespace vscan::client
