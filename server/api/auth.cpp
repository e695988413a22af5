#include "api/auth.h"

#include <strings.h>

#include <openssl/crypto.h>

namespace vscan::api {
namespace {

// "<scheme> <credentials>": the scheme compares case-insensitively (RFC 7235), the token in
// constant time.
bool IsBearer(std::string_view header, const std::string& token) {
  const size_t space = header.find(' ');
  if (space == std::string_view::npos) return false;
  if (space != 6 || strncasecmp(header.data(), "Bearer", 6) != 0) return false;
  const size_t start = header.find_first_not_of(' ', space);
  if (start == std::string_view::npos) return false;
  const std::string_view credentials = header.substr(start);
  return credentials.size() == token.size() && CRYPTO_memcmp(credentials.data(), token.data(), token.size()) == 0;
}

}  // namespace

Status CheckToken(const grpc::ServerContextBase& context, const std::string& token) {
  if (token.empty()) return Status::Ok();
  const auto& metadata = context.client_metadata();
  auto it = metadata.find("authorization");
  if (it != metadata.end() && IsBearer(std::string_view(it->second.data(), it->second.size()), token)) {
    return Status::Ok();
  }
  return {StatusCode::kUnauthenticated, "authorization: missing or wrong bearer token"};
}

}  // namespace vscan::api
