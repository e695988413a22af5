#pragma once
// One `vscan scan` as a user runs it: a new process and channel, the cloud written to a file.

#include <string>
#include <vector>

#include "child_process.h"
#include "run_table.h"
#include "vscan/common/pose.h"
#include "vscan/v1/scan.pb.h"

namespace vscan::bench {

struct CliScan {
  std::string vscan_path;
  std::string server;       // host:port
  std::string output_path;  // .ply or .pcd
  std::string fields;       // as --fields takes them
};

// The `vscan --json scan` command line for request's scene and pinhole camera at world_from_sensor.
std::vector<std::string> CliScanArgv(const CliScan& cli, const v1::ScanRequest& request, const Pose3& world_from_sensor);

// Runs `vscan --json scan` for request's scene and pinhole camera at world_from_sensor; ms is the
// process's whole life. Throws when the command fails.
RunFigures RunCliScan(const CliScan& cli, const v1::ScanRequest& request, const Pose3& world_from_sensor,
                      const std::string& scratch_dir);

}  // namespace vscan::bench
