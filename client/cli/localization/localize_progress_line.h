#pragma once
// A search's progress on stderr while `vscan localize` waits: redrawn in place on a terminal, one
// line per change of stage otherwise (--progress into a file or a pipe).

#include <chrono>
#include <string>

#include "vscan/v1/localization.pb.h"

namespace vscan::cli {

class LocalizeProgressLine {
 public:
  explicit LocalizeProgressLine(bool terminal) : terminal_(terminal) {}
  ~LocalizeProgressLine() { Finish(); }
  LocalizeProgressLine(const LocalizeProgressLine&) = delete;
  LocalizeProgressLine& operator=(const LocalizeProgressLine&) = delete;

  void Update(const v1::LocalizeProgress& progress);
  // Erases the line on a terminal so that later output starts clean.
  void Finish();

 private:
  bool terminal_;
  bool drawn_ = false;
  std::string last_stage_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace vscan::cli
