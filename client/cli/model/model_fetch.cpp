#include "model/model_fetch.h"

#include "model/model_report.h"

namespace vscan::cli {

int FetchArtifactText(Context& ctx, const v1::Job& job, std::string_view name, std::optional<std::string>* text) {
  const v1::Artifact* found = nullptr;
  for (const v1::Artifact& artifact : job.artifacts()) {
    if (artifact.name() == name) found = &artifact;
  }
  if (found == nullptr) return kExitOk;
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  std::string bytes_read;
  const auto read = client->ReadArtifact(job.job_id(), found->artifact_id(), [&](std::string_view bytes) {
    bytes_read.append(bytes);
    return Status::Ok();
  });
  if (!read.ok()) return ctx.ServerError(read.status());
  *text = std::move(bytes_read);
  return kExitOk;
}

int FetchModelReport(Context& ctx, const v1::Job& job, std::optional<v1::ModelReport>* report) {
  std::optional<std::string> text;
  if (const int rc = FetchArtifactText(ctx, job, kModelReportName, &text); rc != kExitOk || !text) return rc;
  auto parsed = ParseModelReport(*text);
  if (!parsed.ok()) return ctx.ServerError(parsed.status());
  *report = std::move(parsed).value();
  return kExitOk;
}

}  // namespace vscan::cli
