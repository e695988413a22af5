#pragma once
// One unary RPC with the client's deadline and credentials, its error converted to a Status.

#include <grpcpp/client_context.h>

#include "vscan/client/client.h"
#include "vscan/common/grpc_status.h"

namespace vscan::client {

template <typename Stub, typename Req, typename Resp>
StatusOr<Resp> UnaryCall(const Client& client, Stub& stub,
                         grpc::Status (Stub::*method)(grpc::ClientContext*, const Req&, Resp*), const Req& request) {
  grpc::ClientContext context;
  client.PrepareContext(&context, client.options().unary_timeout);
  Resp response;
  const grpc::Status status = (stub.*method)(&context, request, &response);
  if (!status.ok()) return FromGrpc(status);
  return response;
}

}  // namespace vscan::client
