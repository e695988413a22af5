#pragma once
// One scan written to a PLY or PCD file as its chunks arrive (no cloud held in memory), with a
// progress bar; shared by `vscan scan` and `vscan bin scan`.

#include <cstdint>
#include <string>

#include "context.h"

namespace vscan::cli {

struct ScannedFile {
  client::ScanResult result;  // header and statistics; the cloud went to the file
  uint64_t points = 0;
  double first_chunk_ms = -1;  // negative: no chunk came
  double total_ms = 0;
};

// Exit 2 unless output ends in .ply or .pcd, 5 when its directory does not exist.
int CheckOutput(Context& ctx, const std::string& output);

// Returns an exit code; the file is complete only when it is kExitOk.
int ScanToFile(Context& ctx, const v1::ScanRequest& request, const std::string& output, ScannedFile* out);

}  // namespace vscan::cli
