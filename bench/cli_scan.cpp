#include "cli_scan.h"

#include <cstdio>
#include <stdexcept>

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

namespace vscan::bench {
namespace {

std::string Joined(std::initializer_list<double> values) {
  std::string out;
  char buf[32];
  for (const double v : values) {
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    out += (out.empty() ? "" : ",") + std::string(buf);
  }
  return out;
}

std::string Number(double v) { return Joined({v}); }

// A number the JSON printer wrote as a number or (64-bit integers) as a string; -1 when absent.
double Field(const google::protobuf::Struct& object, const std::string& name) {
  const auto it = object.fields().find(name);
  if (it == object.fields().end()) return -1;
  if (it->second.has_number_value()) return it->second.number_value();
  if (it->second.has_string_value()) return std::stod(it->second.string_value());
  return -1;
}

}  // namespace

std::vector<std::string> CliScanArgv(const CliScan& cli, const v1::ScanRequest& request, const Pose3& world_from_sensor) {
  const v1::PinholeCamera& p = request.sensor().pinhole();
  const Eigen::Matrix4d m = world_from_sensor.matrix();
  std::string pose;
  for (int r = 0; r < 4; ++r) pose += (r ? "," : "") + Joined({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return {cli.vscan_path, "--server", cli.server, "--json", "scan", request.scene_id(), "-o", cli.output_path,
          "--width", std::to_string(p.width()), "--height", std::to_string(p.height()), "--intrinsics",
          Joined({p.intrinsics().fx(), p.intrinsics().fy(), p.intrinsics().cx(), p.intrinsics().cy()}), "--near",
          Number(p.near()), "--far", Number(p.far()), "--pose-matrix", pose, "--fields", cli.fields};
}

RunFigures RunCliScan(const CliScan& cli, const v1::ScanRequest& request, const Pose3& world_from_sensor,
                      const std::string& scratch_dir) {
  const ProcessRun run = RunProcess(CliScanArgv(cli, request, world_from_sensor), scratch_dir);
  std::remove(cli.output_path.c_str());
  google::protobuf::Struct json;
  if (run.exit_code != 0 || !google::protobuf::util::JsonStringToMessage(run.output, &json).ok()) {
    throw std::runtime_error("vscan scan exited with " + std::to_string(run.exit_code) + ": " + run.output);
  }
  const auto& stats = json.fields().at("statistics").struct_value();
  RunFigures figures;
  figures.ms = run.wall_ms;
  figures.cpu_ms = run.cpu_ms;
  figures.points = Field(stats, "points");
  figures.server_ms = Field(stats, "totalMs");
  figures.client_ms = Field(json, "clientMs");
  figures.first_ms = Field(json, "firstChunkMs");
  return figures;
}

}  // namespace vscan::bench
