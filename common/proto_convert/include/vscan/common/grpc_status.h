#pragma once
// The one place where vscan::Status and grpc::Status meet.

#include <grpcpp/support/status.h>

#include "vscan/common/status.h"

namespace vscan {

grpc::Status ToGrpc(const Status& status);
Status FromGrpc(const grpc::Status& status);

}  // namespace vscan
