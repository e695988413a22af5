#pragma once
// A server stream of stored bytes (an artifact, a cloud): checks done, the bytes loaded on a worker
// thread, then written in chunks of at most 1 MiB, one at a time, the first with its metadata.

#include <algorithm>
#include <functional>
#include <string>

#include <grpcpp/support/server_callback.h>
#include <spdlog/spdlog.h>

#include "jobs/worker_pool.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {

// Response has `set_chunk(bytes)`; the loader fills the bytes and the first message's metadata.
template <typename Response>
class BlobStreamReactor final : public grpc::ServerWriteReactor<Response> {
 public:
  using Loader = std::function<Status(std::string* bytes, Response* first)>;

  // checked is the outcome of the token and request checks: an error ends the call at once.
  BlobStreamReactor(const Status& checked, const char* method, jobs::WorkerPool& workers, Loader load)
      : method_(method), load_(std::move(load)) {
    if (!checked.ok()) {
      Fail(checked);
      return;
    }
    if (!workers.Post([this] { Load(); })) Fail(Unavailable("server is shutting down"));
  }

  void OnWriteDone(bool ok) override {
    if (!ok) {
      this->Finish(grpc::Status(grpc::StatusCode::CANCELLED, "reader went away"));
      return;
    }
    if (offset_ >= bytes_.size()) {
      this->Finish(grpc::Status::OK);
      return;
    }
    response_.Clear();
    WriteChunk();
  }

  void OnDone() override { delete this; }

 private:
  static constexpr size_t kChunkBytes = 1u << 20;

  void Load() {
    const Status loaded = load_(&bytes_, &response_);
    if (!loaded.ok()) {
      Fail(loaded);
      return;
    }
    WriteChunk();
  }

  void WriteChunk() {
    const size_t count = std::min(kChunkBytes, bytes_.size() - offset_);
    response_.set_chunk(bytes_.substr(offset_, count));
    offset_ += count;
    this->StartWrite(&response_);
  }

  void Fail(const Status& status) {
    spdlog::info("{} -> {}", method_, status.ToString());
    this->Finish(ToGrpc(status));
  }

  const char* method_;
  Loader load_;
  std::string bytes_;
  size_t offset_ = 0;
  Response response_;
};

}  // namespace vscan::api
