#pragma once
// Every kind of job JobService runs, in one table: the name the catalogue stores and how its
// stored spec becomes the Job message's. A new kind adds its row here, its folder under
// server/service/ and its Start call (docs/ARCHITECTURE.md, "Adding a job kind").

#include <string>
#include <string_view>

#include "service/job/job_kind.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

struct JobKindRow {
  service::JobKind kind;
  std::string_view spec_noun;  // "campaign spec", as errors name it
  // Parses a stored spec into its field of out; false when the bytes do not parse.
  bool (*read_spec)(const std::string& bytes, v1::Job* out);
};

// The row of a stored kind name; null for a name no row has.
const JobKindRow* FindJobKind(std::string_view name);

}  // namespace vscan::api
