#include "service/context/scan_admission.h"

#include <string>

namespace vscan::service {

ScanSlot& ScanSlot::operator=(ScanSlot&& other) noexcept {
  if (this != &other) {
    Release();
    owner_ = other.owner_;
    other.owner_ = nullptr;
  }
  return *this;
}

void ScanSlot::Release() {
  if (owner_ == nullptr) return;
  owner_->running_.fetch_sub(1);
  owner_ = nullptr;
}

StatusOr<ScanSlot> ScanAdmission::Admit() {
  if (running_.fetch_add(1) >= max_running_) {
    running_.fetch_sub(1);
    return ResourceExhausted("scan: " + std::to_string(max_running_) + " scans already running; retry later");
  }
  return ScanSlot(this);
}

}  // namespace vscan::service
