#include "vscan/common/report_json.h"

#include <google/protobuf/util/json_util.h>

namespace vscan {

std::string PrintReport(const google::protobuf::Message& report) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string out;
  // Printing a well-formed message cannot fail: it holds no Any to resolve.
  (void)google::protobuf::util::MessageToJsonString(report, &out, options);
  return out + "\n";
}

Status ParseReport(std::string_view text, const std::string& name, google::protobuf::Message* report) {
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = true;
  const auto parsed = google::protobuf::util::JsonStringToMessage(std::string(text), report, options);
  if (!parsed.ok()) return DataLoss(name + ": not a report the schema reads: " + std::string(parsed.message()));
  return Status::Ok();
}

}  // namespace vscan
