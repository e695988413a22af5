#include "table_reporter.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace vscan::bench {

benchmark::internal::Benchmark* AddMinMax(benchmark::internal::Benchmark* b) {
  return b->ComputeStatistics("min", [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); })
      ->ComputeStatistics("max", [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); });
}

TableReporter::TableReporter(std::string baseline, std::vector<Column> columns)
    : baseline_(std::move(baseline)), columns_(std::move(columns)) {}

void TableReporter::ReportRuns(const std::vector<Run>& runs) {
  for (const Run& run : runs) {
    if (run.run_type != Run::RT_Aggregate) continue;
    const std::string& name = run.run_name.function_name;
    if (!rows_.contains(name)) order_.push_back(name);
    Row& row = rows_[name];
    const double t = run.GetAdjustedRealTime();
    if (run.aggregate_name == "median") {
      row.median = t;
      for (const auto& [counter, value] : run.counters) row.counters[counter] = value.value;
    } else if (run.aggregate_name == "min") {
      row.min = t;
    } else if (run.aggregate_name == "max") {
      row.max = t;
    }
  }
  ConsoleReporter::ReportRuns(runs);
}

void TableReporter::PrintTable() const {
  const auto base = rows_.find(baseline_);
  // The baseline first, then by name: with random interleaving the run order means nothing.
  std::vector<std::string> order = order_;
  std::sort(order.begin(), order.end(), [this](const std::string& a, const std::string& b) {
    return std::make_pair(a != baseline_, a) < std::make_pair(b != baseline_, b);
  });
  std::printf("\n| case | median ms | min–max ms |");
  for (const Column& c : columns_) std::printf(" %s |", c.header.c_str());
  std::printf(" time / %s |\n|---|---|---|", baseline_.c_str());
  for (size_t i = 0; i <= columns_.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (const std::string& name : order) {
    const Row& row = rows_.at(name);
    std::printf("| %s | %.1f | %.1f–%.1f |", name.c_str(), row.median, row.min, row.max);
    for (const Column& c : columns_) {
      const auto it = row.counters.find(c.counter);
      std::printf(" ");
      if (it != row.counters.end()) {
        std::printf(c.format.c_str(), it->second);
      } else {
        std::printf("–");
      }
      std::printf(" |");
    }
    if (base != rows_.end() && base->second.median > 0) {
      std::printf(" %.2f |\n", row.median / base->second.median);
    } else {
      std::printf(" – |\n");
    }
  }
}

}  // namespace vscan::bench
