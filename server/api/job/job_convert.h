#pragma once
// Job catalogue records <-> wire messages.

#include "service/job/job_events.h"
#include "store/job_catalogue.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

v1::JobState ToProto(store::JobState state);
// DATA_LOSS when the stored description does not parse.
Status ToProto(const store::ArtifactRecord& artifact, v1::Artifact* out);
// The whole job: the spec it was started with (campaign or model) and every artifact.
Status ToProto(const store::JobRecord& job, v1::Job* out);
void SetTime(int64_t ms, google::protobuf::Timestamp* out);
void ToProto(const service::ScanAlignmentRecord& scan, v1::ScanAlignment* out);

}  // namespace vscan::api
