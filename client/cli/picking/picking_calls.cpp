#include "picking/picking_calls.h"

#include <grpcpp/client_context.h>

#include "vscan/common/grpc_status.h"
#include "vscan/v1/picking.grpc.pb.h"

namespace vscan::cli {

StatusOr<v1::GenerateGraspsResponse> CallGenerateGrasps(const client::Client& client,
                                                        const v1::GenerateGraspsRequest& request) {
  auto stub = v1::PickingService::NewStub(client.channel());
  grpc::ClientContext context;
  client.PrepareContext(&context, client.options().stream_timeout);
  v1::GenerateGraspsResponse response;
  const grpc::Status status = stub->GenerateGrasps(&context, request, &response);
  if (!status.ok()) return FromGrpc(status);
  return response;
}

StatusOr<v1::CheckPicksResponse> CallCheckPicks(const client::Client& client, const v1::CheckPicksRequest& request) {
  auto stub = v1::PickingService::NewStub(client.channel());
  grpc::ClientContext context;
  client.PrepareContext(&context, client.options().stream_timeout);
  v1::CheckPicksResponse response;
  const grpc::Status status = stub->CheckPicks(&context, request, &response);
  if (!status.ok()) return FromGrpc(status);
  return response;
}

}  // namespace vscan::cli
