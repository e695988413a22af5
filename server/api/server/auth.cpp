#include "api/server/auth.h"

#include <strings.h>

#include <array>

#include <openssl/crypto.h>
#include <openssl/evp.h>

namespace vscan::api {
namespace {

using Digest = std::array<unsigned char, 32>;

bool Sha256(std::string_view text, Digest& digest) {
  unsigned int size = 0;
  return EVP_Digest(text.data(), text.size(), digest.data(), &size, EVP_sha256(), nullptr) == 1 &&
         size == digest.size();
}

// "<scheme> <credentials>": the scheme compares case-insensitively (RFC 7235), the token in
// constant time. Comparing SHA-256 digests keeps the token's length from showing in the timing.
bool IsBearer(std::string_view header, const std::string& token) {
  const size_t space = header.find(' ');
  if (space == std::string_view::npos) return false;
  if (space != 6 || strncasecmp(header.data(), "Bearer", 6) != 0) return false;
  const size_t start = header.find_first_not_of(' ', space);
  if (start == std::string_view::npos) return false;
  const std::string_view credentials = header.substr(start);
  Digest sent{};
  Digest expected{};
  if (!Sha256(credentials, sent) || !Sha256(token, expected)) return false;
  return CRYPTO_memcmp(sent.data(), expected.data(), sent.size()) == 0;
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
