#include "localization/localization_calls.h"

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
