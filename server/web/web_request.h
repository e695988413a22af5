#pragma once
// One request to the web view's API and its reply, apart from HTTP, with the helpers every
// handler uses (statuses, ids, query values).

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/common/status.h"

namespace vscan::web {

struct WebRequest {
  std::string_view method;
  // The path after "/api/", split at '/': "jobs/job_1/events" is {"jobs", "job_1", "events"}.
  std::vector<std::string_view> segments;
  // The query string without '?', still percent-encoded.
  std::string_view query;

  // The decoded value of key in the query, or nullopt.
  std::optional<std::string> Query(std::string_view key) const;
};

// Writes bytes to the client; false once the client has gone (the stream should then return).
using WebWrite = std::function<bool(std::string_view bytes)>;

struct WebReply {
  int status = 200;
  std::string content_type;
  std::string body;
  // A streamed reply (server-sent events): when set, the headers go out without a length and this
  // is called to write the body piece by piece; body is then unused.
  std::function<void(const WebWrite& write)> stream;
  // The streamed body's size when known in advance (sent as Content-Length); -1: unknown.
  long long stream_length = -1;
};

inline constexpr const char* kJsonType = "application/json";
inline constexpr const char* kBinaryType = "application/octet-stream";

WebReply TextReply(int status, std::string message);
WebReply JsonReply(std::string json);
// A service status as HTTP: NOT_FOUND 404, INVALID_ARGUMENT and OUT_OF_RANGE 400, FAILED_PRECONDITION 409,
// RESOURCE_EXHAUSTED 422; anything else is logged and answered 500 without its detail.
WebReply FromStatus(const Status& status);

// An id is one path segment of letters, digits, '_' and '-' (the catalogue's "scn_...", "job_...").
bool IsId(std::string_view id);

// The query value key as an integer in [min, max]; fallback when absent. INVALID_ARGUMENT naming
// key for anything else.
StatusOr<long long> QueryInteger(const WebRequest& request, std::string_view key, long long fallback,
                                 long long min, long long max);

}  // namespace vscan::web
