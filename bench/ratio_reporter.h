#pragma once
// Console output, then each chosen case's wall time over a baseline's, from medians when the
// benchmark is repeated: ratios in one run hold when this shared machine's speed drifts.

#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

namespace vscan::bench {

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  // Cases whose name contains one of `cases` are divided by the case named `baseline`.
  RatioReporter(std::string baseline, std::vector<std::string> cases);

  void ReportRuns(const std::vector<Run>& runs) override;
  void PrintRatios() const;

 private:
  double Time(const std::string& name) const;

  std::string baseline_;
  std::vector<std::string> cases_;
  // Run name -> (is the median -> real time).
  std::map<std::string, std::map<bool, double>> times_;
};

// benchmark's main with a RatioReporter.
int RunWithRatios(int argc, char** argv, RatioReporter& reporter);

}  // namespace vscan::bench
