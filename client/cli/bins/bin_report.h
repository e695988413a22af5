#pragma once
// A bin fill's bin.json read back from the server (into its message, proto/vscan/v1/reports.proto)
// and summed up in a few lines.

#include <optional>
#include <string>

#include "session/context.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::cli {

// Sets *report to the job's parsed bin.json, or leaves it empty when the job has none. Returns an
// exit code (3 for a report that cannot be read or parsed).
int FetchBinReport(Context& ctx, const v1::Job& job, std::optional<v1::BinReport>* report);

// "settled: 20 of 20 parts in the bin, 0 outside; 6.3 s simulated in 1512 steps ..." and the
// deepest overlaps, one line each.
std::string FormatBinReport(const v1::BinReport& report);

}  // namespace vscan::cli
