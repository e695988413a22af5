#include "vscan/common/status.h"

#include <cstdio>
#include <cstdlib>

namespace vscan {

const char* StatusCodeName(StatusCode code) {
  switch (code) {
    case StatusCode::kOk: return "OK";
    case StatusCode::kCancelled: return "CANCELLED";
    case StatusCode::kUnknown: return "UNKNOWN";
    case StatusCode::kInvalidArgument: return "INVALID_ARGUMENT";
    case StatusCode::kDeadlineExceeded: return "DEADLINE_EXCEEDED";
    case StatusCode::kNotFound: return "NOT_FOUND";
    case StatusCode::kAlreadyExists: return "ALREADY_EXISTS";
    case StatusCode::kResourceExhausted: return "RESOURCE_EXHAUSTED";
    case StatusCode::kFailedPrecondition: return "FAILED_PRECONDITION";
    case StatusCode::kOutOfRange: return "OUT_OF_RANGE";
    case StatusCode::kUnimplemented: return "UNIMPLEMENTED";
    case StatusCode::kInternal: return "INTERNAL";
    case StatusCode::kUnavailable: return "UNAVAILABLE";
    case StatusCode::kDataLoss: return "DATA_LOSS";
    case StatusCode::kUnauthenticated: return "UNAUTHENTICATED";
  }
  return "UNKNOWN";
}

bool NamesAField(StatusCode code) {
  switch (code) {
    case StatusCode::kInvalidArgument:
    case StatusCode::kNotFound:
    case StatusCode::kFailedPrecondition:
    case StatusCode::kOutOfRange:
    case StatusCode::kUnimplemented:
    case StatusCode::kResourceExhausted: return true;
    default: return false;
  }
}

Status::Status(StatusCode code, std::string field, std::string_view text) : code_(code), field_(std::move(field)) {
  if (field_.empty()) {
    message_ = text;
    return;
  }
  message_.reserve(field_.size() + 2 + text.size());
  message_ += field_;
  message_ += ": ";
  message_ += text;
}

std::string_view Status::text() const {
  std::string_view m = message_;
  return field_.empty() ? m : m.substr(field_.size() + 2);
}

Status Status::WithFieldPrefix(std::string_view parent) const {
  if (ok()) return *this;
  if (field_.empty()) return Status(code_, std::string(parent), message_);
  return Status(code_, FieldPath(parent, field_), text());
}

Status Status::WithCode(StatusCode code) const {
  Status out = *this;
  out.code_ = code;
  return out;
}

std::string Status::ToString() const {
  if (ok()) return "OK";
  return std::string(StatusCodeName(code_)) + ": " + message_;
}

namespace internal {

void DieOnValueOfError(const Status& status) {
  std::fprintf(stderr, "vscan: value() of an error StatusOr: %s\n", status.ToString().c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace internal

}  // namespace vscan
