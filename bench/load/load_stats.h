#pragma once
// What the clients of vscan-load record, and its summary: counts, errors by code and
// latency percentiles per kind of call.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace vscan::cli {

enum class LoadKind { kScan = 0, kIk = 1, kCatalogue = 2 };
inline constexpr size_t kLoadKinds = 3;
const char* LoadKindName(LoadKind kind);

struct LatencySummary {
  size_t count = 0;
  double p50_ms = 0;
  double p99_ms = 0;
  double max_ms = 0;
  double mean_ms = 0;
};

// Nearest-rank percentiles (the smallest sample with at least p of them at or below it).
LatencySummary Summarize(std::vector<double> samples_ms);

// What one client saw; merged across clients for the report.
struct LoadTally {
  // Latencies of the calls that succeeded, per kind.
  std::array<std::vector<double>, kLoadKinds> ok_ms;
  // Failed calls per kind, by status code name.
  std::array<std::map<std::string, uint64_t>, kLoadKinds> errors;
  uint64_t scan_points = 0;

  void Merge(const LoadTally& other);
  uint64_t Ok(LoadKind kind) const { return ok_ms[static_cast<size_t>(kind)].size(); }
  uint64_t Failed(LoadKind kind) const;
};

}  // namespace vscan::cli
