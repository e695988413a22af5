#pragma once
// A one-line progress bar on stderr, redrawn in place; silent unless stderr is a terminal.

#include <chrono>
#include <cstdint>
#include <string>

namespace vscan::cli {

class ProgressBar {
 public:
  // enabled is further ANDed with "stderr is a TTY".
  ProgressBar(std::string label, std::string unit, bool enabled);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // total 0 means unknown.
  void Update(uint64_t done, uint64_t total);
  // Erases the bar so that later output starts on a clean line.
  void Finish();

 private:
  void Draw(uint64_t done, uint64_t total);

  std::string label_;
  std::string unit_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace vscan::cli
