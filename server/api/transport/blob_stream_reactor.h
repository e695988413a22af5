#pragma once
// A server stream of stored bytes (an artifact, a cloud): checks done, the blob opened and its hash
// checked on a worker thread, then read from disk and written in chunks of at most 1 MiB, one at a
// time, the first with its metadata. At most one chunk is in memory whatever the blob's size, and a
// client that stops reading is cancelled after the stalled-reader limit.

#include <algorithm>
#include <functional>
#include <optional>
#include <string>

#include <grpcpp/support/server_callback.h>
#include <spdlog/spdlog.h>

#include "api/transport/write_watch.h"
#include "jobs/worker_pool.h"
#include "store/blob_reader.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {

// Response has `set_chunk(bytes)`; the opener opens the blob and fills the first message's metadata.
template <typename Response>
class BlobStreamReactor final : public grpc::ServerWriteReactor<Response> {
 public:
  using Opener = std::function<StatusOr<store::BlobReader>(Response* first)>;

  // checked is the outcome of the token and request checks: an error ends the call at once.
  // stalled_readers (may be null) cancels the call when a write waits on its client too long.
  BlobStreamReactor(const Status& checked, const char* method, grpc::CallbackServerContext* ctx,
                    jobs::WorkerPool& workers, guards::StallWatchdog* stalled_readers, Opener open)
      : method_(method), open_(std::move(open)), write_watch_(stalled_readers, ctx) {
    if (!checked.ok()) {
      Fail(checked);
      return;
    }
    if (!workers.Post([this] { Open(); })) Fail(Unavailable("server is shutting down"));
  }

  void OnWriteDone(bool ok) override {
    write_watch_.Done();
    if (!ok) {
      this->Finish(grpc::Status(grpc::StatusCode::CANCELLED, "reader went away"));
      return;
    }
    if (offset_ >= reader_->size()) {
      this->Finish(grpc::Status::OK);
      return;
    }
    response_.Clear();
    WriteChunk();
  }

  void OnDone() override {
    write_watch_.Release();
    delete this;
  }

 private:
  static constexpr size_t kChunkBytes = 1u << 20;

  void Open() {
    auto opened = open_(&response_);
    if (!opened.ok()) {
      Fail(opened.status());
      return;
    }
    reader_.emplace(std::move(opened).value());
    WriteChunk();
  }

  void WriteChunk() {
    auto chunk = reader_->Read(offset_, kChunkBytes);
    if (!chunk.ok()) {
      Fail(chunk.status());
      return;
    }
    offset_ += chunk->size();
    response_.set_chunk(std::move(chunk).value());
    write_watch_.Started(method_);
    this->StartWrite(&response_);
  }

  void Fail(const Status& status) {
    spdlog::info("{} -> {}", method_, status.ToString());
    this->Finish(ToGrpc(status));
  }

  const char* method_;
  Opener open_;
  WriteWatch write_watch_;
  std::optional<store::BlobReader> reader_;
  uint64_t offset_ = 0;
  Response response_;
};

}  // namespace vscan::api
