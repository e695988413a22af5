#pragma once
// Per-run figures of benchmark cases gathered over rounds, printed as min/median/max rows.

#include <string>
#include <vector>

namespace vscan::bench {

struct Spread {
  double min = 0, median = 0, max = 0;
};

// Of a non-empty set of values.
Spread SpreadOf(std::vector<double> values);

// One timed run of a case; first_ms and client_ms are negative when not known.
struct RunFigures {
  double ms = 0;         // what the caller waited for
  double points = 0;
  double client_ms = -1;  // the client's own connect-to-last-chunk time, when it is not ms
  double server_ms = -1;  // the server's reported total
  double first_ms = -1;   // call to first chunk
  double cpu_ms = -1;     // the client's user + system time
};

class RunTable {
 public:
  void Add(const std::string& name, const RunFigures& run);
  // One row a case, in the order first added; ratios to the median ms of the baseline case.
  void Print(const std::string& baseline) const;

 private:
  struct Case {
    std::string name;
    std::vector<RunFigures> runs;
  };
  std::vector<Case> cases_;
};

}  // namespace vscan::bench
