#include "api/scan/scan_outbox.h"

namespace vscan::api {

ScanOutbox::ScanOutbox(size_t window, std::function<void(const v1::ScanResponse*)> start_write,
                       std::function<void(const grpc::Status&)> finish)
    : window_(window < 2 ? 2 : window), start_write_(std::move(start_write)), finish_(std::move(finish)) {}

void ScanOutbox::Push(std::unique_ptr<v1::ScanResponse> message) {
  std::unique_lock lock(mutex_);
  if (broken_ || finished_) return;
  queue_.push_back(std::move(message));
  StartOrFinish(lock);
}

void ScanOutbox::Close(const grpc::Status& status) {
  std::unique_lock lock(mutex_);
  closed_ = true;
  if (!end_) end_ = status;
  StartOrFinish(lock);
}

bool ScanOutbox::HasRoom() {
  std::lock_guard lock(mutex_);
  return queue_.size() < window_ || cancelled_;
}

void ScanOutbox::WaitForRoom() {
  std::unique_lock lock(mutex_);
  room_.wait(lock, [&] { return cancelled_ || queue_.size() <= window_ / 2; });
}

void ScanOutbox::WriteDone(bool ok) {
  std::unique_lock lock(mutex_);
  writing_ = false;
  if (!ok) {
    broken_ = cancelled_ = true;
    queue_.clear();
    end_ = grpc::Status(grpc::StatusCode::CANCELLED, "client went away");
  } else {
    queue_.pop_front();
  }
  room_.notify_all();
  StartOrFinish(lock);
}

void ScanOutbox::Cancel() {
  std::lock_guard lock(mutex_);
  cancelled_ = true;
  room_.notify_all();
}

// Called with the lock held; releases it before calling out.
void ScanOutbox::StartOrFinish(std::unique_lock<std::mutex>& lock) {
  if (writing_ || finished_) return;
  if (!queue_.empty() && !broken_) {
    writing_ = true;
    const v1::ScanResponse* next = queue_.front().get();
    lock.unlock();
    start_write_(next);
    return;
  }
  if (!closed_ || !queue_.empty()) return;
  finished_ = true;
  const grpc::Status status = *end_;
  lock.unlock();
  finish_(status);
}

}  // namespace vscan::api
