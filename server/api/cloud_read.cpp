// CloudService.ReadCloud: a cloud's binary PLY in chunks of at most 1 MiB, the first with its
// metadata.

#include <algorithm>

#include <spdlog/spdlog.h>

#include "api/auth.h"
#include "api/cloud_convert.h"
#include "api/cloud_service.h"
#include "api/validate.h"
#include "service/cloud_store.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {
namespace {

constexpr size_t kChunkBytes = 1u << 20;

// The blob is read on a worker thread; writes then proceed one at a time.
class ReadCloudReactor final : public grpc::ServerWriteReactor<v1::ReadCloudResponse> {
 public:
  ReadCloudReactor(grpc::CallbackServerContext* ctx, const v1::ReadCloudRequest& request,
                   service::ServiceContext& context)
      : cloud_id_(request.cloud_id()), context_(context) {
    Status status = CheckToken(*ctx, context.options.token);
    if (status.ok()) status = RequireId(cloud_id_, "cloud_id");
    if (!status.ok()) {
      Fail(status);
      return;
    }
    if (!context.workers.Post([this] { Load(); })) Fail(Unavailable("server is shutting down"));
  }

  void OnWriteDone(bool ok) override {
    if (!ok) {
      Finish(grpc::Status(grpc::StatusCode::CANCELLED, "reader went away"));
      return;
    }
    WriteNext();
  }

  void OnDone() override { delete this; }

 private:
  void Load() {
    auto stored = service::LoadCloud(context_, cloud_id_);
    if (!stored.ok()) {
      Fail(stored.status());
      return;
    }
    ToProto(stored->record, response_.mutable_cloud());
    bytes_ = std::move(stored->ply);
    WriteChunk();
  }

  void WriteChunk() {
    const size_t count = std::min(kChunkBytes, bytes_.size() - offset_);
    response_.set_chunk(bytes_.substr(offset_, count));
    offset_ += count;
    StartWrite(&response_);
  }

  void WriteNext() {
    if (offset_ >= bytes_.size()) {
      Finish(grpc::Status::OK);
      return;
    }
    response_.Clear();
    WriteChunk();
  }

  void Fail(const Status& status) {
    spdlog::info("ReadCloud -> {}", status.ToString());
    Finish(ToGrpc(status));
  }

  const std::string cloud_id_;
  service::ServiceContext& context_;
  std::string bytes_;
  size_t offset_ = 0;
  v1::ReadCloudResponse response_;
};

}  // namespace

grpc::ServerWriteReactor<v1::ReadCloudResponse>* CloudService::ReadCloud(grpc::CallbackServerContext* ctx,
                                                                         const v1::ReadCloudRequest* request) {
  return new ReadCloudReactor(ctx, *request, context_);
}

}  // namespace vscan::api
