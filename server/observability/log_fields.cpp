#include "observability/log_fields.h"

namespace vscan::observability {
namespace {

thread_local std::vector<LogField> current_fields;

}  // namespace

const std::vector<LogField>& CurrentLogFields() { return current_fields; }

LogFieldsScope::LogFieldsScope(std::vector<LogField> fields) : added_(fields.size()) {
  for (LogField& field : fields) current_fields.push_back(std::move(field));
}

LogFieldsScope::~LogFieldsScope() { current_fields.resize(current_fields.size() - added_); }

}  // namespace vscan::observability
