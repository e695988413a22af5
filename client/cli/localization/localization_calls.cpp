#include "localization/localization_calls.h"

#include <optional>

#include <grpcpp/client_context.h>

#include "vscan/common/grpc_status.h"
#include "vscan/v1/localization.grpc.pb.h"

namespace vscan::cli {

StatusOr<v1::LocalizeResponse> CallLocalize(const client::Client& client, const v1::LocalizeRequest& request) {
  auto stub = v1::LocalizationService::NewStub(client.channel());
  grpc::ClientContext context;
  client.PrepareContext(&context, client.options().stream_timeout);
  v1::LocalizeResponse response;
  const grpc::Status status = stub->Localize(&context, request, &response);
  if (!status.ok()) return FromGrpc(status);
  return response;
}

StatusOr<v1::LocalizeResponse> CallLocalizeWithProgress(
    const client::Client& client, const v1::LocalizeRequest& request,
    const std::function<void(const v1::LocalizeProgress&)>& on_progress) {
  auto stub = v1::LocalizationService::NewStub(client.channel());
  grpc::ClientContext context;
  client.PrepareContext(&context, client.options().stream_timeout);
  v1::LocalizeWithProgressRequest streamed;
  *streamed.mutable_localize() = request;
  auto reader = stub->LocalizeWithProgress(&context, streamed);
  v1::LocalizeWithProgressResponse message;
  std::optional<v1::LocalizeResponse> response;
  while (reader->Read(&message)) {
    if (message.has_progress()) on_progress(message.progress());
    if (message.has_response()) response = std::move(*message.mutable_response());
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return FromGrpc(status);
  if (!response) return Internal("LocalizeWithProgress ended without a response");
  return *response;
}

StatusOr<v1::ScorePosesResponse> CallScorePoses(const client::Client& client, const v1::ScorePosesRequest& request) {
  auto stub = v1::LocalizationService::NewStub(client.channel());
  grpc::ClientContext context;
  client.PrepareContext(&context, client.options().unary_timeout);
  v1::ScorePosesResponse response;
  const grpc::Status status = stub->ScorePoses(&context, request, &response);
  if (!status.ok()) return FromGrpc(status);
  return response;
}

}  // namespace vscan::cli
