#pragma once
// model.json (the report of a model job, or of a campaign that aligned its scans; docs/MODEL.md)
// as text: the alignment, the reconstruction, the verdict against the truth, the next best views.

#include <string>
#include <string_view>

#include <google/protobuf/struct.pb.h>

#include "vscan/common/status.h"
#include "vscan/v1/model.pb.h"

namespace vscan::cli {

// The name a model job's report has among its artifacts.
inline constexpr std::string_view kModelReportName = "model.json";

// DATA_LOSS unless text is a JSON object.
StatusOr<google::protobuf::Struct> ParseModelReport(std::string_view text);
// Lines ending in '\n'; sections the report leaves out (the parts that did not run) are left out.
std::string FormatModelReport(const google::protobuf::Struct& report);
// The report as JSON on one line, for --json.
std::string ModelReportJson(const google::protobuf::Struct& report);

// One line for a scan as it is aligned: index, cloud, fitness and the pose error when known, or
// why it was not aligned.
std::string FormatScanAlignment(const v1::ScanAlignment& alignment);

}  // namespace vscan::cli
