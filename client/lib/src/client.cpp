#include "vscan/client/client.h"

#include <fstream>
#include <sstream>

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>

#include "unary_call.h"

namespace vscan::client {
namespace {

StatusOr<std::string> ReadPem(const std::string& path, const char* option) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(std::string(option) + ": cannot read " + path);
  std::ostringstream pem;
  pem << in.rdbuf();
  return pem.str();
}

StatusOr<std::shared_ptr<grpc::ChannelCredentials>> Credentials(const ClientOptions& options) {
  if (options.tls_client_cert_path.empty() != options.tls_client_key_path.empty()) {
    return InvalidArgument("tls_client_cert_path and tls_client_key_path go together");
  }
  const bool tls = options.use_tls || !options.tls_root_cert_path.empty() || !options.tls_client_cert_path.empty();
  if (!tls) return grpc::InsecureChannelCredentials();
  grpc::SslCredentialsOptions ssl;
  // Empty roots: gRPC's default roots (GRPC_DEFAULT_SSL_ROOTS_FILE_PATH or the system's).
  if (!options.tls_root_cert_path.empty()) {
    ASSIGN_OR_RETURN(ssl.pem_root_certs, ReadPem(options.tls_root_cert_path, "tls_root_cert_path"));
  }
  if (!options.tls_client_cert_path.empty()) {
    ASSIGN_OR_RETURN(ssl.pem_cert_chain, ReadPem(options.tls_client_cert_path, "tls_client_cert_path"));
    ASSIGN_OR_RETURN(ssl.pem_private_key, ReadPem(options.tls_client_key_path, "tls_client_key_path"));
  }
  return grpc::SslCredentials(ssl);
}

}  // namespace

StatusOr<Client> Client::Connect(const std::string& target, const ClientOptions& options) {
  if (target.empty()) return InvalidArgument("target: empty server address");
  // gRPC aborts the process on a header value it cannot send; refuse such a token here instead.
  for (const unsigned char c : options.bearer_token) {
    if (c < 0x21 || c > 0x7e) {
      return InvalidArgument("bearer_token: only visible ASCII characters (no spaces, newlines or control characters)");
    }
  }
  ASSIGN_OR_RETURN(auto credentials, Credentials(options));
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(options.max_receive_bytes);
  if (options.stream_window_bytes > 0) {
    args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
    args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, options.stream_window_bytes);
  }
  return Client(grpc::CreateCustomChannel(target, credentials, args), options);
}

Client::Client(std::shared_ptr<grpc::Channel> channel, ClientOptions options)
    : options_(std::move(options)),
      channel_(std::move(channel)),
      scenes_(v1::SceneService::NewStub(channel_)),
      scans_(v1::ScanService::NewStub(channel_)),
      health_(grpc::health::v1::Health::NewStub(channel_)) {}

Client::Client(Client&&) noexcept = default;
Client& Client::operator=(Client&&) noexcept = default;
Client::~Client() = default;

void Client::PrepareContext(grpc::ClientContext* context, std::chrono::milliseconds timeout) const {
  if (timeout.count() > 0) context->set_deadline(std::chrono::system_clock::now() + timeout);
  if (!options_.bearer_token.empty()) context->AddMetadata("authorization", "Bearer " + options_.bearer_token);
}

StatusOr<grpc::health::v1::HealthCheckResponse> Client::Health(const std::string& service) {
  grpc::health::v1::HealthCheckRequest request;
  request.set_service(service);
  return UnaryCall(*this, *health_, &grpc::health::v1::Health::Stub::Check, request);
}

StatusOr<std::vector<v1::SensorPreset>> Client::ListSensorPresets() {
  const v1::ListSensorPresetsRequest request;
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *scans_, &v1::ScanService::Stub::ListSensorPresets, request));
  return std::vector<v1::SensorPreset>(response.presets().begin(), response.presets().end());
}

}  // namespace vscan::client
