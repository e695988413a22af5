#pragma once
// Console output, then one Markdown row per benchmark (the baseline first, the rest by name) with
// its median, min and max wall time over the repetitions, chosen counters (their medians) and the
// median's ratio to the baseline's.
// Benchmarks need Repetitions and the "min" and "max" statistics (see AddMinMax).

#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

namespace vscan::bench {

// Adds the "min" and "max" statistics the table reads.
benchmark::internal::Benchmark* AddMinMax(benchmark::internal::Benchmark* b);

class TableReporter : public benchmark::ConsoleReporter {
 public:
  // `columns` are (counter name, header, printf format) in table order.
  struct Column {
    std::string counter;
    std::string header;
    std::string format;
  };
  TableReporter(std::string baseline, std::vector<Column> columns);

  void ReportRuns(const std::vector<Run>& runs) override;
  void PrintTable() const;

 private:
  struct Row {
    double median = 0, min = 0, max = 0;
    std::map<std::string, double> counters;
  };

  std::string baseline_;
  std::vector<Column> columns_;
  std::vector<std::string> order_;
  std::map<std::string, Row> rows_;
};

}  // namespace vscan::bench
