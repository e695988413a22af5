// CloudService.UploadCloud: collects the client stream within --max-upload-mib, then imports it on
// a worker thread.

#include <string>

#include <spdlog/spdlog.h>

#include "api/clouds/cloud_convert.h"
#include "api/clouds/cloud_service.h"
#include "api/transport/upload_reactor.h"

namespace vscan::api {
namespace {

class UploadCloudReactor final : public UploadReactor<v1::UploadCloudRequest> {
 public:
  UploadCloudReactor(grpc::CallbackServerContext* ctx, v1::UploadCloudResponse* response,
                     service::ServiceContext& context)
      : UploadReactor(ctx, context, "UploadCloud"), response_(response) {
    Start();
  }

 private:
  uint64_t limit() const { return context_.options.limits.max_upload_bytes; }

  Status Accept(const v1::UploadCloudRequest& request) override {
    if (request.has_header()) {
      if (has_header_) return InvalidArgument("header", "sent twice; only the first message is a header");
      has_header_ = true;
      header_ = request.header();
      ASSIGN_OR_RETURN(upload_, CloudUploadFromProto(header_));
      if (header_.size_bytes() > limit()) {
        return ResourceExhausted("header.size_bytes", std::to_string(header_.size_bytes()) +
                                                          " bytes exceed the upload limit of " +
                                                          std::to_string(limit()) + " (--max-upload-mib)");
      }
      return Status::Ok();
    }
    if (!has_header_) return InvalidArgument("header", "the first message must carry the header");
    if (bytes_.size() + request.chunk().size() > limit()) {
      return ResourceExhausted("chunk", "upload exceeds the limit of " + std::to_string(limit()) +
                                            " bytes (--max-upload-mib)");
    }
    bytes_ += request.chunk();
    return Status::Ok();
  }

  Status Complete() override {
    if (!has_header_) return InvalidArgument("header", "the first message must carry the header");
    if (header_.size_bytes() != 0 && header_.size_bytes() != bytes_.size()) {
      return InvalidArgument("header.size_bytes", "announced " + std::to_string(header_.size_bytes()) +
                                                      " bytes, the upload sent " + std::to_string(bytes_.size()));
    }
    auto cloud = service::ImportCloud(context_, bytes_, upload_);
    if (!cloud.ok()) return InHeader(cloud.status());
    spdlog::info("cloud {}: uploaded '{}', {} points, {} bytes stored", cloud->cloud_id, cloud->name, cloud->points,
                 cloud->size_bytes);
    ToProto(*cloud, response_->mutable_cloud());
    return Status::Ok();
  }

  v1::UploadCloudResponse* response_;
  v1::CloudHeader header_;
  service::CloudUpload upload_;
  bool has_header_ = false;
  std::string bytes_;
};

}  // namespace

grpc::ServerReadReactor<v1::UploadCloudRequest>* CloudService::UploadCloud(grpc::CallbackServerContext* ctx,
                                                                           v1::UploadCloudResponse* response) {
  return new UploadCloudReactor(ctx, response, context_);
}

}  // namespace vscan::api
