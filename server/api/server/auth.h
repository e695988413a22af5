#pragma once
// Bearer-token check shared by every service.

#include <string>

#include <grpcpp/server_context.h>

#include "vscan/common/status.h"

namespace vscan::api {

// OK when no token is configured or the call carries "authorization: Bearer <token>".
Status CheckToken(const grpc::ServerContextBase& context, const std::string& token);

}  // namespace vscan::api
