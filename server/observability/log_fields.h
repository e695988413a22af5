#pragma once
// Named values that the log lines a thread writes carry besides their message: JSON keys in the
// json format, key=value at the end of a text line.

#include <string>
#include <vector>

namespace vscan::observability {

struct LogField {
  std::string key;
  std::string value;
  // Written without quotes in JSON (the value must then be a JSON number).
  bool number = false;
};

// The fields in force on the calling thread, innermost scope last.
const std::vector<LogField>& CurrentLogFields();

// Adds fields to the thread's log lines for its lifetime.
class LogFieldsScope {
 public:
  explicit LogFieldsScope(std::vector<LogField> fields);
  ~LogFieldsScope();
  LogFieldsScope(const LogFieldsScope&) = delete;
  LogFieldsScope& operator=(const LogFieldsScope&) = delete;

 private:
  size_t added_;
};

}  // namespace vscan::observability
