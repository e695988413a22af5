#include "ratio_reporter.h"

#include <cstdio>
#include <utility>

namespace vscan::bench {

RatioReporter::RatioReporter(std::string baseline, std::vector<std::string> cases)
    : baseline_(std::move(baseline)), cases_(std::move(cases)) {}

void RatioReporter::ReportRuns(const std::vector<Run>& runs) {
  for (const Run& run : runs) {
    const bool median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
    if (median || run.run_type == Run::RT_Iteration) times_[run.run_name.str()][median] = run.GetAdjustedRealTime();
  }
  ConsoleReporter::ReportRuns(runs);
}

void RatioReporter::PrintRatios() const {
  const double base = Time(baseline_);
  if (base <= 0) return;
  for (const auto& [name, unused] : times_) {
    bool chosen = false;
    for (const std::string& c : cases_) chosen = chosen || name.find(c) != std::string::npos;
    const double t = Time(name);
    if (chosen && t > 0) std::printf("%s / %s time ratio: %.3f\n", name.c_str(), baseline_.c_str(), t / base);
  }
}

double RatioReporter::Time(const std::string& name) const {
  for (const std::string& key : {name, name + "/real_time"}) {
    const auto it = times_.find(key);
    if (it == times_.end()) continue;
    const auto median = it->second.find(true);
    return median != it->second.end() ? median->second : it->second.at(false);
  }
  return 0;
}

int RunWithRatios(int argc, char** argv, RatioReporter& reporter) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintRatios();
  benchmark::Shutdown();
  return 0;
}

}  // namespace vscan::bench
