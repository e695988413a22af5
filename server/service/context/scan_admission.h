#pragma once
// How many scans run at once: a slot per running scan, refused past the limit.

#include <atomic>
#include <cstdint>

#include "vscan/common/status.h"

namespace vscan::service {

class ScanAdmission;

// A running scan's slot; released when destroyed.
class ScanSlot {
 public:
  ScanSlot() = default;
  ScanSlot(ScanSlot&& other) noexcept : owner_(other.owner_) { other.owner_ = nullptr; }
  ScanSlot& operator=(ScanSlot&& other) noexcept;
  ScanSlot(const ScanSlot&) = delete;
  ScanSlot& operator=(const ScanSlot&) = delete;
  ~ScanSlot() { Release(); }

  bool held() const { return owner_ != nullptr; }
  void Release();

 private:
  friend class ScanAdmission;
  explicit ScanSlot(ScanAdmission* owner) : owner_(owner) {}
  ScanAdmission* owner_ = nullptr;
};

class ScanAdmission {
 public:
  explicit ScanAdmission(uint32_t max_running) : max_running_(max_running) {}

  // RESOURCE_EXHAUSTED when max_running scans already hold a slot.
  StatusOr<ScanSlot> Admit();
  uint32_t running() const { return running_.load(); }

 private:
  friend class ScanSlot;
  const uint32_t max_running_;
  std::atomic<uint32_t> running_{0};
};

}  // namespace vscan::service
