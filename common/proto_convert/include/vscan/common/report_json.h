#pragma once
// The JSON of the reports jobs leave (model.json, campaign.json, bin.json), printed from and parsed
// into their messages in proto/vscan/v1/reports.proto, with the options both sides share: keys are
// the fields' names, every field without presence prints even at its default, unknown keys are
// passed over (a newer server's report still reads).

#include <string>
#include <string_view>

#include <google/protobuf/message.h>

#include "vscan/common/status.h"

namespace vscan {

// One JSON object ending in '\n'.
std::string PrintReport(const google::protobuf::Message& report);
// DATA_LOSS naming `name` ("model.json") unless text is a JSON object of report's type.
Status ParseReport(std::string_view text, const std::string& name, google::protobuf::Message* report);

}  // namespace vscan
