#pragma once
// model.json (the report of a model job, or of a campaign that aligned its scans; docs/MODEL.md)
// as text: the alignment, the reconstruction, the verdict against the truth, the next best views.

#include <string>
#include <string_view>

#include <google/protobuf/message.h>

#include "vscan/common/status.h"
#include "vscan/v1/model.pb.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::cli {

// The name a model job's report has among its artifacts.
inline constexpr std::string_view kModelReportName = "model.json";

// DATA_LOSS unless text is a JSON object the schema (proto/vscan/v1/reports.proto) reads; keys it
// does not know are passed over.
StatusOr<v1::ModelReport> ParseModelReport(std::string_view text);
// Lines ending in '\n'; sections the report leaves out (the parts that did not run) are left out.
std::string FormatModelReport(const v1::ModelReport& report);
// A report (model.json, bin.json) as JSON on one line with the file's keys, for --json.
std::string ReportJson(const google::protobuf::Message& report);

// One line for a scan as it is aligned: index, cloud, fitness and the pose error when known, or
// why it was not aligned.
std::string FormatScanAlignment(const v1::ScanAlignment& alignment);

}  // namespace vscan::cli
