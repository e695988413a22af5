// Reads scoring cases from stdin and prints vscan's errors and scores for each as one JSON line,
// for bench/bop_score_check.py to hold against bop_toolkit_lib. Input, whitespace separated:
//   <cases>; per case: <parts>; per part: <id> <n> n x (x y z) <discrete> d x (R row-major, t)
//   <continuous> c x (axis, point); <truths> t x (part R t visible_fraction);
//   <estimates> e x (part R t score); <add_threshold> <min_visible_fraction> <keep_top 0|1>.
// Output per case: per part the diameter, every estimate-truth pair's ADD, ADD-S and MSSD, and
// ScoreScan's result (per part and pooled).

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "localization/bop_scoring.h"
#include "localization/part_symmetries.h"
#include "localization/pose_errors.h"

namespace {

using vscan::Pose3;
using namespace vscan::localization;

template <typename T>
T Read() {
  T value{};
  if (!(std::cin >> value)) {
    std::fprintf(stderr, "bop_score_cases: truncated input\n");
    std::exit(2);
  }
  return value;
}

Pose3 ReadPose() {
  Pose3 pose = Pose3::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) pose.matrix()(r, c) = Read<double>();
  }
  for (int r = 0; r < 3; ++r) pose.matrix()(r, 3) = Read<double>();
  return pose;
}

std::string Number(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

std::string Optional(const std::optional<double>& v) { return v ? Number(*v) : "null"; }

std::string List(const std::vector<double>& values) {
  std::string out = "[";
  for (size_t i = 0; i < values.size(); ++i) out += (i ? "," : "") + Number(values[i]);
  return out + "]";
}

std::string PairErrors(const PartDefinition& part, std::span<const TrueInstance> truth,
                       std::span<const EstimatedInstance> estimates) {
  const std::vector<Pose3> symmetries = SymmetryTransforms(part.symmetries);
  std::string out = "[";
  bool first = true;
  for (size_t e = 0; e < estimates.size(); ++e) {
    if (estimates[e].part_id != part.part_id) continue;
    for (size_t g = 0; g < truth.size(); ++g) {
      if (truth[g].part_id != part.part_id) continue;
      const Pose3& p = estimates[e].world_from_part;
      const Pose3& q = truth[g].world_from_part;
      out += std::string(first ? "" : ",") + "[" + std::to_string(e) + "," + std::to_string(g) + "," +
             Number(AddError(part.vertices, p, q)) + "," + Number(AddSError(part.vertices, p, q)) + "," +
             Number(MssdError(part.vertices, p, q, symmetries)) + "]";
      first = false;
    }
  }
  return out + "]";
}

std::string PartJson(const PartDefinition& part, const PartScore& score, std::span<const TrueInstance> truth,
                     std::span<const EstimatedInstance> estimates) {
  std::string out = "{\"id\":" + std::to_string(score.part_id) + ",\"diameter\":" + Number(score.diameter) +
                    ",\"uses_add_s\":" + (score.uses_add_s ? "true" : "false") +
                    ",\"valid\":" + std::to_string(score.valid_instances) +
                    ",\"add_correct\":" + std::to_string(score.add_correct) +
                    ",\"add_recall\":" + Optional(score.add_recall) +
                    ",\"mssd_average_recall\":" + Optional(score.mssd_average_recall) +
                    ",\"mssd_recalls\":" + List(score.mssd_recalls) + ",\"matches\":[";
  for (size_t i = 0; i < score.instances.size(); ++i) {
    const InstanceResult& r = score.instances[i];
    out += std::string(i ? "," : "") + "[" + std::to_string(r.true_index) + "," +
           (r.estimate_index ? std::to_string(*r.estimate_index) : "-1") + "," + Number(r.add_error) + "," +
           Number(r.mssd_error) + "]";
  }
  return out + "],\"pairs\":" + PairErrors(part, truth, estimates) + "}";
}

}  // namespace

int main() {
  std::ios::sync_with_stdio(false);
  const int cases = Read<int>();
  for (int c = 0; c < cases; ++c) {
    std::vector<PartDefinition> parts(Read<size_t>());
    for (PartDefinition& part : parts) {
      part.part_id = Read<uint32_t>();
      part.vertices.resize(Read<size_t>());
      for (auto& v : part.vertices) {
        for (int k = 0; k < 3; ++k) v[k] = Read<float>();
      }
      part.symmetries.discrete.resize(Read<size_t>());
      for (Pose3& s : part.symmetries.discrete) s = ReadPose();
      part.symmetries.continuous.resize(Read<size_t>());
      for (ContinuousSymmetry& s : part.symmetries.continuous) {
        for (int k = 0; k < 3; ++k) s.axis[k] = Read<double>();
        for (int k = 0; k < 3; ++k) s.point[k] = Read<double>();
      }
    }
    std::vector<TrueInstance> truth(Read<size_t>());
    for (TrueInstance& t : truth) {
      t.part_id = Read<uint32_t>();
      t.world_from_part = ReadPose();
      t.visible_fraction = Read<double>();
    }
    std::vector<EstimatedInstance> estimates(Read<size_t>());
    for (EstimatedInstance& e : estimates) {
      e.part_id = Read<uint32_t>();
      e.world_from_part = ReadPose();
      e.score = Read<double>();
    }
    ScoringOptions options;
    options.add_threshold = Read<double>();
    options.min_visible_fraction = Read<double>();
    options.keep_top_estimates = Read<int>() != 0;

    const auto score = ScoreScan(parts, truth, estimates, options);
    if (!score.ok()) {
      std::printf("{\"error\":\"%s\"}\n", score.status().ToString().c_str());
      continue;
    }
    std::string line = "{\"add_recall\":" + Optional(score->add_recall) +
                       ",\"mssd_average_recall\":" + Optional(score->mssd_average_recall) +
                       ",\"mssd_thresholds\":" + List(BopMssdThresholds()) + ",\"parts\":[";
    for (size_t i = 0; i < parts.size(); ++i) {
      line += (i ? "," : "") + PartJson(parts[i], score->parts[i], truth, estimates);
    }
    std::printf("%s]}\n", line.c_str());
  }
  return 0;
}
