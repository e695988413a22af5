#pragma once
// What a bin fill reports, kept for the test: its events, bin.json and its end; it can stop the
// job at the first event whose message contains stop_when.

#include <string>
#include <vector>

#include "api/reports/proto_report_writer.h"
#include "jobs/job_runner.h"
#include "service/job/job_events.h"

namespace vscan::service::testing {

class RecordedFill final : public JobRecorder {
 public:
  jobs::JobControl control;   // the run's, for RunBinFill
  std::string stop_when;      // empty: never stop

  Status Record(const JobEventUpdate& update) override {
    messages.push_back(update.message);
    if (!stop_when.empty() && update.message.find(stop_when) != std::string::npos) {
      control.RequestStop(jobs::StopReason::kCancelled);
    }
    return Status::Ok();
  }
  StatusOr<std::string> RecordArtifact(const std::string& name, const std::string&, const std::string& bytes,
                                       const ScanArtifact*, const store::CloudRecord*,
                                       const JobEventUpdate&) override {
    if (name == "bin.json") bin_json = bytes;
    return std::string("art_1");
  }
  Status End(const JobEventUpdate& update) override {
    end_state = update.state;
    end_message = update.message;
    return Status::Ok();
  }
  const ReportWriter& reports() const override { return reports_; }

  api::ProtoReportWriter reports_;
  std::vector<std::string> messages;
  std::string bin_json;
  store::JobState end_state = store::JobState::kRunning;
  std::string end_message;
};

}  // namespace vscan::service::testing
