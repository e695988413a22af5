#pragma once
// The messages of one Scan stream between the thread that produces them and gRPC: a bounded
// window of ready messages, written one at a time in order. The producer waits (or pauses its
// cast) while the window is full, so a slow client holds back the scan instead of the server
// buffering the cloud.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>

#include <grpcpp/support/status.h>

#include "vscan/v1/scan.pb.h"

namespace vscan::api {

class ScanOutbox {
 public:
  // start_write hands one message to StartWrite, finish ends the call; both run outside the lock,
  // each message stays alive until its WriteDone, and finish runs once.
  ScanOutbox(size_t window, std::function<void(const v1::ScanResponse*)> start_write,
             std::function<void(const grpc::Status&)> finish);

  // Producer side. Push queues a message (dropped once the client has gone); Close ends the stream
  // after the queued messages with status, and is the producer's last use of the outbox.
  void Push(std::unique_ptr<v1::ScanResponse> message);
  void Close(const grpc::Status& status);
  bool HasRoom();
  // Until the window has drained to half or Cancel was called.
  void WaitForRoom();

  // gRPC side: after each write (ok false: the client went away); Cancel wakes a waiting producer.
  void WriteDone(bool ok);
  void Cancel();

 private:
  void StartOrFinish(std::unique_lock<std::mutex>& lock);

  const size_t window_;
  const std::function<void(const v1::ScanResponse*)> start_write_;
  const std::function<void(const grpc::Status&)> finish_;
  std::mutex mutex_;
  std::condition_variable room_;
  // The front is being written while writing_.
  std::deque<std::unique_ptr<v1::ScanResponse>> queue_;
  bool writing_ = false;
  bool broken_ = false;
  bool cancelled_ = false;
  bool closed_ = false;
  bool finished_ = false;
  std::optional<grpc::Status> end_;
};

}  // namespace vscan::api
