#include "picking/pick_report.h"

#include <cmath>
#include <cstdio>

#include "session/text_format.h"

namespace vscan::cli {
namespace {

// The translation and the z axis of a pose the server wrote as a row-major matrix.
struct ToolAxes {
  double x = 0, y = 0, z = 0, ax = 0, ay = 0, az = 0;
};

ToolAxes AxesOf(const v1::Pose& pose) {
  ToolAxes out;
  if (!pose.has_matrix() || pose.matrix().values_size() != 16) return out;
  const auto& v = pose.matrix().values();
  out.x = v[3];
  out.y = v[7];
  out.z = v[11];
  out.ax = v[2];
  out.ay = v[6];
  out.az = v[10];
  return out;
}

// Without a sign on values that round to zero ("-0.000").
std::string Rounded(double value, int digits) {
  return Fixed(std::fabs(value) < 0.5 * std::pow(10.0, -digits) ? 0.0 : value, digits);
}

std::string Triple(double a, double b, double c, int digits) {
  return "(" + Rounded(a, digits) + ", " + Rounded(b, digits) + ", " + Rounded(c, digits) + ")";
}

}  // namespace

std::string PickFailureWord(v1::PickFailure failure) {
  if (failure == v1::PICK_FAILURE_UNSPECIFIED) return "PICKABLE";
  const std::string name = v1::PickFailure_Name(failure);
  const std::string prefix = "PICK_FAILURE_";
  return name.rfind(prefix, 0) == 0 ? name.substr(prefix.size()) : name;
}

std::vector<std::string> GraspLines(const v1::GenerateGraspsResponse& response) {
  std::vector<std::string> lines;
  lines.push_back(std::to_string(response.grasps_size()) + " grasps in " + Fixed(response.elapsed_ms(), 1) +
                  " ms, best first (part frame, metres)");
  char line[256];
  std::snprintf(line, sizeof(line), "%5s %8s  %-30s %-25s %s", "#", "quality", "tool position", "approach",
                "opening mm");
  lines.push_back(line);
  for (int i = 0; i < response.grasps_size(); ++i) {
    const v1::Grasp& grasp = response.grasps(i);
    const ToolAxes tool = AxesOf(grasp.part_from_tool());
    const std::string position = Triple(tool.x, tool.y, tool.z, 4);
    const std::string approach = Triple(grasp.approach().x(), grasp.approach().y(), grasp.approach().z(), 3);
    std::snprintf(line, sizeof(line), "%5d %8.3f  %-30s %-25s %.1f", i, grasp.quality(), position.c_str(),
                  approach.c_str(), grasp.opening() * 1000);
    lines.push_back(line);
  }
  return lines;
}

std::vector<std::string> PickLines(const v1::CheckPicksResponse& response) {
  std::vector<std::string> lines;
  for (const v1::PartPick& part : response.parts()) {
    std::string line = part.label() + "  " + part.object_id() + "  ";
    if (part.pickable()) {
      const ToolAxes tool = AxesOf(part.world_from_tool());
      line += "pickable: grasp " + std::to_string(part.grasp_index()) + ", tool at " +
              Triple(tool.x, tool.y, tool.z, 4) + ", approach " + Triple(tool.ax, tool.ay, tool.az, 3);
    } else {
      line += PickFailureWord(part.failure());
      if (!part.detail().empty()) line += ": " + part.detail();
      if (!part.covered_by_object_id().empty()) line += "; covered by " + part.covered_by_object_id();
    }
    lines.push_back(line);
  }
  lines.push_back(std::to_string(response.pickable()) + " of " + std::to_string(response.parts_size()) +
                  " parts pickable (scene " + response.scene_id() + ", " + std::to_string(response.grasps_generated()) +
                  " grasps generated, " + Fixed(response.elapsed_ms(), 1) + " ms on the server)");
  return lines;
}

}  // namespace vscan::cli
