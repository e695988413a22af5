#pragma once
// One scan written to a PLY or PCD file as its chunks arrive (no cloud held in memory), with a
// progress bar; shared by `vscan scan` and `vscan bin scan`.

#include <cstdint>
#include <string>

#include "session/context.h"

namespace vscan::cli {

struct ScannedFile {
  client::ScanResult result;  // header and statistics; the cloud went to the file
  uint64_t points = 0;
  double first_chunk_ms = -1;  // negative: no chunk came
  double total_ms = 0;
};

// Exit 2 unless output ends in .ply or .pcd (only .pcd when organized), 5 when its directory does
// not exist.
int CheckOutput(Context& ctx, const std::string& output, bool organized = false);

// Returns an exit code; the file is complete only when it is kExitOk. organized: the file is the
// range image, an organised PCD (organized_pcd.h) of the camera's width x height with the sensor pose
// as VIEWPOINT; the pixel field is asked for when the request lacks it, and the cloud is held in
// memory until the scan ends.
int ScanToFile(Context& ctx, const v1::ScanRequest& request, const std::string& output, ScannedFile* out,
               bool organized = false);

}  // namespace vscan::cli
