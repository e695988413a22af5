#include "model_fetch.h"

#include "model_report.h"

namespace vscan::cli {

int FetchModelReport(Context& ctx, const v1::Job& job, std::optional<google::protobuf::Struct>* report) {
  const v1::Artifact* found = nullptr;
  for (const v1::Artifact& artifact : job.artifacts()) {
    if (artifact.name() == kModelReportName) found = &artifact;
  }
  if (found == nullptr) return kExitOk;
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  std::string text;
  const auto read = client->ReadArtifact(job.job_id(), found->artifact_id(), [&](std::string_view bytes) {
    text.append(bytes);
    return Status::Ok();
  });
  if (!read.ok()) return ctx.ServerError(read.status());
  auto parsed = ParseModelReport(text);
  if (!parsed.ok()) return ctx.ServerError(parsed.status());
  *report = std::move(parsed).value();
  return kExitOk;
}

}  // namespace vscan::cli
