#pragma once
// A running job's events and artifacts into the job tracker, scan descriptions as the
// contract's ScanArtifactInfo, captured scans as stored clouds, reports through their messages.

#include <string>

#include "api/job/job_tracker.h"
#include "api/reports/proto_report_writer.h"
#include "service/job/job_events.h"

namespace vscan::api {

class TrackedJobRecorder final : public service::JobRecorder {
 public:
  TrackedJobRecorder(JobTracker& tracker, std::string job_id) : tracker_(tracker), job_id_(std::move(job_id)) {}

  Status Record(const service::JobEventUpdate& update) override;
  StatusOr<std::string> RecordArtifact(const std::string& name, const std::string& media_type,
                                       const std::string& bytes, const service::ScanArtifact* scan,
                                       const store::CloudRecord* cloud, const service::JobEventUpdate& update) override;
  Status End(const service::JobEventUpdate& update) override;
  const service::ReportWriter& reports() const override { return reports_; }

 private:
  JobTracker& tracker_;
  const std::string job_id_;
  ProtoReportWriter reports_;
};

}  // namespace vscan::api
