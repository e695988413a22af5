#include "run_table.h"

#include <algorithm>
#include <cstdio>
#include <functional>

namespace vscan::bench {
namespace {

// Values of f over the runs where it is known (not negative).
std::vector<double> Known(const std::vector<RunFigures>& runs, const std::function<double(const RunFigures&)>& f) {
  std::vector<double> out;
  for (const RunFigures& r : runs) {
    if (const double v = f(r); v >= 0) out.push_back(v);
  }
  return out;
}

std::string Cell(const std::vector<double>& values, const char* format) {
  if (values.empty()) return "-";
  const Spread s = SpreadOf(values);
  char buf[96];
  std::snprintf(buf, sizeof(buf), format, s.min, s.median, s.max);
  return buf;
}

}  // namespace

Spread SpreadOf(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  const double median = n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
  return {values.front(), median, values.back()};
}

void RunTable::Add(const std::string& name, const RunFigures& run) {
  auto it = std::find_if(cases_.begin(), cases_.end(), [&](const Case& c) { return c.name == name; });
  if (it == cases_.end()) it = cases_.insert(cases_.end(), Case{name, {}});
  it->runs.push_back(run);
}

void RunTable::Print(const std::string& baseline) const {
  double base_ms = 0;
  for (const Case& c : cases_) {
    if (c.name == baseline) base_ms = SpreadOf(Known(c.runs, [](const RunFigures& r) { return r.ms; })).median;
  }
  std::printf("%-40s %3s %-20s %-17s %-20s %-17s %-17s %-15s %-15s %-17s %s\n", "case", "n", "ms min/med/max",
              "Mpts/s min/med/max", "client ms", "client Mpts/s", "server total ms", "first chunk ms", "first share",
              "client cpu ms", "ms/base");
  const auto per_ms = [](double points, double ms) { return ms > 0 ? points / ms / 1e3 : -1; };
  for (const Case& c : cases_) {
    const auto ms = Known(c.runs, [](const RunFigures& r) { return r.ms; });
    const auto client_ms = Known(c.runs, [](const RunFigures& r) { return r.client_ms >= 0 ? r.client_ms : r.ms; });
    const auto share = Known(c.runs, [](const RunFigures& r) {
      const double whole = r.client_ms >= 0 ? r.client_ms : r.ms;
      return r.first_ms >= 0 && whole > 0 ? r.first_ms / whole : -1;
    });
    const double ratio = base_ms > 0 ? SpreadOf(ms).median / base_ms : 0;
    std::printf("%-40s %3zu %-20s %-17s %-20s %-17s %-17s %-15s %-15s %-17s %.2f\n", c.name.c_str(), c.runs.size(),
                Cell(ms, "%.1f/%.1f/%.1f").c_str(),
                Cell(Known(c.runs, [&](const RunFigures& r) { return per_ms(r.points, r.ms); }), "%.1f/%.1f/%.1f")
                    .c_str(),
                Cell(client_ms, "%.1f/%.1f/%.1f").c_str(),
                Cell(Known(c.runs,
                           [&](const RunFigures& r) {
                             return per_ms(r.points, r.client_ms >= 0 ? r.client_ms : r.ms);
                           }),
                     "%.1f/%.1f/%.1f")
                    .c_str(),
                Cell(Known(c.runs, [](const RunFigures& r) { return r.server_ms; }), "%.1f/%.1f/%.1f").c_str(),
                Cell(Known(c.runs, [](const RunFigures& r) { return r.first_ms; }), "%.1f/%.1f/%.1f").c_str(),
                Cell(share, "%.2f/%.2f/%.2f").c_str(),
                Cell(Known(c.runs, [](const RunFigures& r) { return r.cpu_ms; }), "%.0f/%.0f/%.0f").c_str(), ratio);
  }
}

}  // namespace vscan::bench
