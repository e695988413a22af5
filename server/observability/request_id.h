#pragma once
// The id of the call a thread is working for, so that every log line written for a call names it.
// Set by the gRPC layer when a call starts; carried onto worker pools and job threads.

#include <string>
#include <string_view>

namespace vscan::observability {

// The calling thread's request id; empty when it works for no call.
const std::string& CurrentRequestId();

// A fresh id: 16 lower-case hex digits.
std::string NewRequestId();

// Whether a client's x-request-id may be used as given: 1 to 64 characters of letters, digits
// and . _ : - (nothing that could break a log line or a header).
bool IsSaneRequestId(std::string_view id);

// Sets the thread's request id for its lifetime and restores the previous one after.
class RequestIdScope {
 public:
  explicit RequestIdScope(std::string id);
  ~RequestIdScope();
  RequestIdScope(const RequestIdScope&) = delete;
  RequestIdScope& operator=(const RequestIdScope&) = delete;

 private:
  std::string previous_;
};

// Wraps work so that it runs under the request id current where it was wrapped.
template <typename Work>
auto CarryRequestId(Work work) {
  return [id = CurrentRequestId(), work = std::move(work)](auto&&... args) mutable {
    RequestIdScope scope(id);
    return work(std::forward<decltype(args)>(args)...);
  };
}

}  // namespace vscan::observability
