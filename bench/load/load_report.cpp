#include "load_report.h"

#include <cstdio>
#include <sstream>

#include "session/context.h"
#include "session/text_format.h"

namespace vscan::cli {
namespace {

double Mib(uint64_t kib) { return static_cast<double>(kib) / 1024.0; }

LatencySummary Overall(const LoadTally& tally) {
  std::vector<double> all;
  for (const auto& samples : tally.ok_ms) all.insert(all.end(), samples.begin(), samples.end());
  return Summarize(std::move(all));
}

std::string ErrorsJson(const std::map<std::string, uint64_t>& errors) {
  std::string json = "{";
  for (const auto& [code, n] : errors) {
    json += (json.size() > 1 ? "," : "") + JsonQuote(code) + ":" + std::to_string(n);
  }
  return json + "}";
}

std::map<std::string, uint64_t> AllErrors(const LoadTally& tally) {
  std::map<std::string, uint64_t> all;
  for (const auto& errors : tally.errors) {
    for (const auto& [code, n] : errors) all[code] += n;
  }
  return all;
}

std::string LatencyJson(const LatencySummary& s) {
  return "{\"ok\":" + std::to_string(s.count) + ",\"p50Ms\":" + Fixed(s.p50_ms, 3) + ",\"p99Ms\":" +
         Fixed(s.p99_ms, 3) + ",\"maxMs\":" + Fixed(s.max_ms, 3) + ",\"meanMs\":" + Fixed(s.mean_ms, 3) + "}";
}

uint64_t Failed(const LoadTally& tally) {
  uint64_t n = 0;
  for (size_t k = 0; k < kLoadKinds; ++k) n += tally.Failed(static_cast<LoadKind>(k));
  return n;
}

double PerSecond(uint64_t n, double seconds) { return seconds > 0 ? static_cast<double>(n) / seconds : 0.0; }

}  // namespace

std::string FormatLoadReportJson(const LoadReport& report) {
  const LoadTally& tally = report.run.tally;
  const LatencySummary all = Overall(tally);
  const uint64_t failed = Failed(tally);
  std::string json = "{\"clients\":" + std::to_string(report.limits.clients) +
                     ",\"width\":" + std::to_string(report.width) + ",\"height\":" + std::to_string(report.height) +
                     ",\"elapsedS\":" + Fixed(report.run.elapsed_s, 3) +
                     ",\"requests\":" + std::to_string(all.count + failed) + ",\"ok\":" + std::to_string(all.count) +
                     ",\"failed\":" + std::to_string(failed) + ",\"errors\":" + ErrorsJson(AllErrors(tally)) +
                     ",\"throughputPerS\":" + Fixed(PerSecond(all.count, report.run.elapsed_s), 3) +
                     ",\"scanPoints\":" + std::to_string(tally.scan_points) + ",\"kinds\":{";
  for (size_t k = 0; k < kLoadKinds; ++k) {
    const auto kind = static_cast<LoadKind>(k);
    const LatencySummary s = Summarize(tally.ok_ms[k]);
    json += std::string(k ? "," : "") + JsonQuote(LoadKindName(kind)) + ":{\"requests\":" +
            std::to_string(s.count + tally.Failed(kind)) + ",\"failed\":" + std::to_string(tally.Failed(kind)) +
            ",\"errors\":" + ErrorsJson(tally.errors[k]) +
            ",\"throughputPerS\":" + Fixed(PerSecond(s.count, report.run.elapsed_s), 3) +
            ",\"latency\":" + LatencyJson(s) + "}";
  }
  json += "},\"latency\":" + LatencyJson(all) + ",\"serverMemory\":";
  if (report.memory && report.memory->samples > 0) {
    const MemorySummary& m = *report.memory;
    json += "{\"pid\":" + std::to_string(*report.server_pid) + ",\"samples\":" + std::to_string(m.samples) +
            ",\"startRssMib\":" + Fixed(Mib(m.start_rss_kib), 1) + ",\"endRssMib\":" + Fixed(Mib(m.end_rss_kib), 1) +
            ",\"peakSampledRssMib\":" + Fixed(Mib(m.peak_sampled_rss_kib), 1) +
            ",\"lifetimePeakRssMib\":" + Fixed(Mib(m.lifetime_peak_rss_kib), 1) + "}";
  } else {
    json += "null";
  }
  return json + "}";
}

std::string FormatLoadReportText(const LoadReport& report) {
  const LoadTally& tally = report.run.tally;
  const LatencySummary all = Overall(tally);
  std::ostringstream out;
  out << report.limits.clients << " clients, " << Fixed(report.run.elapsed_s, 1) << " s, scans of " << report.width
      << "x" << report.height << ": " << all.count << " calls ok, " << Failed(tally) << " failed, "
      << Fixed(PerSecond(all.count, report.run.elapsed_s), 1) << " calls/s\n";
  out << "kind         ok  failed    per s   p50 ms   p99 ms   max ms\n";
  const auto row = [&](const std::string& name, const LatencySummary& s, uint64_t failed) {
    char line[160];
    std::snprintf(line, sizeof line, "%-9s %5zu %7llu %8.1f %8.1f %8.1f %8.1f\n", name.c_str(), s.count,
                  static_cast<unsigned long long>(failed), PerSecond(s.count, report.run.elapsed_s), s.p50_ms,
                  s.p99_ms, s.max_ms);
    out << line;
  };
  for (size_t k = 0; k < kLoadKinds; ++k) {
    const auto kind = static_cast<LoadKind>(k);
    row(LoadKindName(kind), Summarize(tally.ok_ms[k]), tally.Failed(kind));
  }
  row("all", all, Failed(tally));
  for (const auto& [code, n] : AllErrors(tally)) out << "  " << code << ": " << n << '\n';
  if (report.memory && report.memory->samples > 0) {
    const MemorySummary& m = *report.memory;
    out << "server " << *report.server_pid << " resident memory: " << Fixed(Mib(m.start_rss_kib), 1)
        << " MiB at the start, peak " << Fixed(Mib(m.peak_sampled_rss_kib), 1) << " MiB sampled ("
        << m.samples << " samples), " << Fixed(Mib(m.end_rss_kib), 1) << " MiB at the end; lifetime peak (VmHWM) "
        << Fixed(Mib(m.lifetime_peak_rss_kib), 1) << " MiB\n";
  } else {
    out << "server memory: unknown (give --server-pid for a server this user cannot see by its port)\n";
  }
  return out.str();
}

}  // namespace vscan::cli
