#pragma once
// Errors as values: a Status with a code, a message, and the path of the offending field.

#include <cassert>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace vscan {

// Mirrors the gRPC codes we use; the api layer maps them one to one.
enum class StatusCode {
  kOk = 0,
  kCancelled = 1,
  kUnknown = 2,
  kInvalidArgument = 3,
  kDeadlineExceeded = 4,
  kNotFound = 5,
  kAlreadyExists = 6,
  kResourceExhausted = 8,
  kFailedPrecondition = 9,
  kOutOfRange = 11,
  kUnimplemented = 12,
  kInternal = 13,
  kUnavailable = 14,
  kDataLoss = 15,
  kUnauthenticated = 16,
};

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  // An error about one request field: field() is its path, message() reads "<field>: <text>"
  // (just the text when field is empty).
  Status(StatusCode code, std::string field, std::string_view text);

  static Status Ok() { return {}; }
  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  // The full human text, "<field>: <text>" when a field is named.
  const std::string& message() const { return message_; }
  // The path of the offending field ("robot.mount_id"); empty when the error names none.
  const std::string& field() const { return field_; }
  // The message without its "<field>: " lead.
  std::string_view text() const;
  // The same error with `parent` prepended to its field path ("robot" + "mount_id"), or naming
  // `parent` itself when it named no field.
  Status WithFieldPrefix(std::string_view parent) const;
  // The same error (field included) under another code.
  Status WithCode(StatusCode code) const;
  std::string ToString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
  std::string field_;
};

const char* StatusCodeName(StatusCode code);
// The codes that judge a request's own values, whose messages start with the field they name;
// false for trouble of the server itself (UNAVAILABLE, INTERNAL, ...).
bool NamesAField(StatusCode code);

namespace internal {
// Prints the status to stderr and aborts: reading the value of an error is a bug, not UB.
[[noreturn]] void DieOnValueOfError(const Status& status);
}  // namespace internal

inline Status InvalidArgument(std::string m) { return {StatusCode::kInvalidArgument, std::move(m)}; }
inline Status NotFound(std::string m) { return {StatusCode::kNotFound, std::move(m)}; }
inline Status FailedPrecondition(std::string m) { return {StatusCode::kFailedPrecondition, std::move(m)}; }
inline Status ResourceExhausted(std::string m) { return {StatusCode::kResourceExhausted, std::move(m)}; }
inline Status OutOfRange(std::string m) { return {StatusCode::kOutOfRange, std::move(m)}; }
inline Status Unimplemented(std::string m) { return {StatusCode::kUnimplemented, std::move(m)}; }
inline Status Internal(std::string m) { return {StatusCode::kInternal, std::move(m)}; }
inline Status Cancelled(std::string m) { return {StatusCode::kCancelled, std::move(m)}; }
inline Status Unavailable(std::string m) { return {StatusCode::kUnavailable, std::move(m)}; }
inline Status DataLoss(std::string m) { return {StatusCode::kDataLoss, std::move(m)}; }

// Errors about one field, which they carry as data (Status::field()).
inline Status InvalidArgument(std::string field, std::string_view text) {
  return {StatusCode::kInvalidArgument, std::move(field), text};
}
inline Status NotFound(std::string field, std::string_view text) {
  return {StatusCode::kNotFound, std::move(field), text};
}
inline Status FailedPrecondition(std::string field, std::string_view text) {
  return {StatusCode::kFailedPrecondition, std::move(field), text};
}
inline Status ResourceExhausted(std::string field, std::string_view text) {
  return {StatusCode::kResourceExhausted, std::move(field), text};
}
inline Status OutOfRange(std::string field, std::string_view text) {
  return {StatusCode::kOutOfRange, std::move(field), text};
}

// "parent.member", the path error messages use to name a nested request field.
inline std::string FieldPath(std::string_view parent, std::string_view member) {
  std::string path(parent);
  path += '.';
  path += member;
  return path;
}

// A value or the Status that explains why there is none.
// Reading the value of an error aborts with the status on stderr, in every build type.
template <typename T>
class [[nodiscard]] StatusOr {
 public:
  StatusOr(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
  StatusOr(Status status) : status_(std::move(status)) {  // NOLINT: implicit by design
    assert(!status_.ok());
    if (status_.ok()) status_ = Status(StatusCode::kInternal, "StatusOr made from an OK Status");
  }

  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  T& value() & { return Checked(); }
  const T& value() const& { return Checked(); }
  T&& value() && { return std::move(Checked()); }
  T* operator->() { return &Checked(); }
  const T* operator->() const { return &Checked(); }
  T& operator*() & { return Checked(); }
  const T& operator*() const& { return Checked(); }

 private:
  T& Checked() {
    if (!value_) internal::DieOnValueOfError(status_);
    return *value_;
  }
  const T& Checked() const {
    if (!value_) internal::DieOnValueOfError(status_);
    return *value_;
  }

  Status status_;
  std::optional<T> value_;
};

}  // namespace vscan

#define VSCAN_CONCAT_INNER(a, b) a##b
#define VSCAN_CONCAT(a, b) VSCAN_CONCAT_INNER(a, b)

#define RETURN_IF_ERROR(expr)                  \
  do {                                         \
    ::vscan::Status _vscan_status = (expr);    \
    if (!_vscan_status.ok()) return _vscan_status; \
  } while (0)

#define ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                          \
  if (!tmp.ok()) return tmp.status();         \
  lhs = std::move(tmp).value()

// ASSIGN_OR_RETURN(auto x, FunctionReturningStatusOr());
#define ASSIGN_OR_RETURN(lhs, expr) ASSIGN_OR_RETURN_IMPL(VSCAN_CONCAT(_vscan_or_, __LINE__), lhs, expr)
