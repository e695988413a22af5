#pragma once
// Stored clouds <-> wire messages: the Cloud a row describes, and an upload's header checked against
// the contract (messages name "header.<field>").

#include "service/clouds/cloud_store.h"
#include "store/cloud_catalogue.h"
#include "vscan/common/status.h"
#include "vscan/v1/cloud.pb.h"

namespace vscan::api {

void ToProto(const store::CloudRecord& cloud, v1::Cloud* out);

// Everything but size_bytes, which the upload reactor checks against the limit.
StatusOr<service::CloudUpload> CloudUploadFromProto(const v1::CloudHeader& header);

// Errors about what the header says gain its path ("header.scene_id"); errors about the file's
// contents ("cloud data: ...") and the server's own troubles stay as they are.
Status InHeader(const Status& status);

}  // namespace vscan::api
