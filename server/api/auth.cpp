#include "api/auth.h"

#include <openssl/crypto.h>

namespace vscan::api {

Status CheckToken(const grpc::ServerContextBase& context, const std::string& token) {
  if (token.empty()) return Status::Ok();
  const auto& metadata = context.client_metadata();
  auto it = metadata.find("authorization");
  const std::string expected = "Bearer " + token;
  if (it != metadata.end() && it->second.size() == expected.size() &&
      CRYPTO_memcmp(it->second.data(), expected.data(), expected.size()) == 0) {
    return Status::Ok();
  }
  return {StatusCode::kUnauthenticated, "authorization: missing or wrong bearer token"};
}

}  // namespace vscan::api
