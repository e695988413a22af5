#include "localization/bop_scoring.h"

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>

#include "localization/pose_errors.h"
#include "localization/pose_matching.h"

namespace vscan::localization {
namespace {

std::string Indexed(const char* list, size_t i, const char* member) {
  return std::string(list) + "[" + std::to_string(i) + "]." + member;
}

Status CheckInputs(std::span<const PartDefinition> parts, std::span<const TrueInstance> truth,
                   std::span<const EstimatedInstance> estimates, const ScoringOptions& options,
                   std::unordered_map<uint32_t, size_t>& part_index) {
  for (size_t i = 0; i < parts.size(); ++i) {
    if (!part_index.emplace(parts[i].part_id, i).second) {
      return InvalidArgument(Indexed("parts", i, "part_id"), "appears twice");
    }
    if (parts[i].vertices.empty()) return InvalidArgument(Indexed("parts", i, "vertices"), "is empty");
    if (!(parts[i].known_diameter >= 0 && std::isfinite(parts[i].known_diameter))) {
      return InvalidArgument(Indexed("parts", i, "known_diameter"), "must be finite and not negative");
    }
    for (const auto& v : parts[i].vertices) {
      if (!v.allFinite()) return InvalidArgument(Indexed("parts", i, "vertices"), "must be finite");
    }
  }
  for (size_t i = 0; i < truth.size(); ++i) {
    if (!part_index.contains(truth[i].part_id)) return InvalidArgument(Indexed("truth", i, "part_id"), "is unknown");
    if (!truth[i].world_from_part.matrix().allFinite()) {
      return InvalidArgument(Indexed("truth", i, "world_from_part"), "must be finite");
    }
    const double f = truth[i].visible_fraction;
    if (!(f >= 0 && f <= 1)) return InvalidArgument(Indexed("truth", i, "visible_fraction"), "must be in [0, 1]");
  }
  for (size_t i = 0; i < estimates.size(); ++i) {
    if (!part_index.contains(estimates[i].part_id)) {
      return InvalidArgument(Indexed("estimates", i, "part_id"), "is unknown");
    }
    if (!estimates[i].world_from_part.matrix().allFinite()) {
      return InvalidArgument(Indexed("estimates", i, "world_from_part"), "must be finite");
    }
    if (!std::isfinite(estimates[i].score)) return InvalidArgument(Indexed("estimates", i, "score"), "must be finite");
  }
  if (!(options.add_threshold > 0)) return InvalidArgument("scoring.add_threshold", "must be positive");
  for (const double t : options.mssd_thresholds) {
    if (!(t > 0)) return InvalidArgument("scoring.mssd_thresholds", "must be positive");
  }
  if (!(options.symmetry_step > 0 && options.symmetry_step <= 1)) {
    return InvalidArgument("scoring.symmetry_step", "must be in (0, 1]");
  }
  return Status::Ok();
}

std::vector<size_t> Count(const std::vector<int>& match) {
  std::vector<size_t> matched;
  for (size_t g = 0; g < match.size(); ++g) {
    if (match[g] != kUnmatched) matched.push_back(g);
  }
  return matched;
}

PartScore ScorePart(const PartDefinition& part, std::span<const TrueInstance> truth,
                    std::span<const EstimatedInstance> estimates, const ScoringOptions& options,
                    const std::vector<double>& mssd_thresholds) {
  PartScore score;
  score.part_id = part.part_id;
  score.diameter = part.known_diameter > 0 ? part.known_diameter : Diameter(part.vertices);
  score.uses_add_s = part.symmetries.any();
  const std::vector<Pose3> symmetries = SymmetryTransforms(part.symmetries, options.symmetry_step);

  std::vector<size_t> truths, ests;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (truth[i].part_id == part.part_id) truths.push_back(i);
  }
  for (size_t i = 0; i < estimates.size(); ++i) {
    if (estimates[i].part_id == part.part_id) ests.push_back(i);
  }
  score.estimates = ests.size();

  // Not std::vector<bool>, which cannot be viewed as a span.
  const auto valid = std::make_unique<bool[]>(truths.size());
  for (size_t g = 0; g < truths.size(); ++g) {
    valid[g] = truth[truths[g]].visible_fraction >= options.min_visible_fraction;
    if (valid[g]) ++score.valid_instances;
  }
  if (score.valid_instances == 0) return score;
  const std::span<const bool> valid_span(valid.get(), truths.size());

  const auto rows = static_cast<Eigen::Index>(ests.size()), cols = static_cast<Eigen::Index>(truths.size());
  constexpr double kNever = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd add = Eigen::MatrixXd::Constant(rows, cols, kNever), mssd = add;
  std::vector<double> scores(ests.size());
  for (Eigen::Index e = 0; e < rows; ++e) {
    const EstimatedInstance& estimate = estimates[ests[static_cast<size_t>(e)]];
    scores[static_cast<size_t>(e)] = estimate.score;
    for (Eigen::Index g = 0; g < cols; ++g) {
      if (!valid[static_cast<size_t>(g)]) continue;
      if (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed)) return score;
      const Pose3& true_pose = truth[truths[static_cast<size_t>(g)]].world_from_part;
      add(e, g) = score.uses_add_s ? AddSError(part.vertices, estimate.world_from_part, true_pose)
                                   : AddError(part.vertices, estimate.world_from_part, true_pose);
      mssd(e, g) = MssdError(part.vertices, estimate.world_from_part, true_pose, symmetries);
    }
  }
  const size_t top = options.keep_top_estimates ? score.valid_instances : 0;
  // BOP divides the errors by the diameter and compares them with the fractions (not the errors
  // with fraction times diameter, which can round the other way at a threshold). Without a
  // diameter nothing is correct.
  const auto by_diameter = [&](const Eigen::MatrixXd& errors) -> Eigen::MatrixXd {
    if (score.diameter > 0) return errors / score.diameter;
    return Eigen::MatrixXd::Constant(rows, cols, kNever);
  };
  const Eigen::MatrixXd add_fraction = by_diameter(add), mssd_fraction = by_diameter(mssd);

  const std::vector<int> add_match = MatchEstimates(scores, add_fraction, valid_span, options.add_threshold, top);
  score.add_correct = Count(add_match).size();
  for (size_t g = 0; g < truths.size(); ++g) {
    if (!valid[g]) continue;
    InstanceResult result;
    result.true_index = truths[g];
    if (add_match[g] != kUnmatched) {
      const auto e = static_cast<size_t>(add_match[g]);
      result.estimate_index = ests[e];
      result.add_error = add(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(g));
      result.mssd_error = mssd(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(g));
    }
    score.instances.push_back(result);
  }
  const auto valid_count = static_cast<double>(score.valid_instances);
  score.add_recall = static_cast<double>(score.add_correct) / valid_count;

  double recall_sum = 0;
  for (const double t : mssd_thresholds) {
    const std::vector<int> match = MatchEstimates(scores, mssd_fraction, valid_span, t, top);
    score.mssd_recalls.push_back(static_cast<double>(Count(match).size()) / valid_count);
    recall_sum += score.mssd_recalls.back();
  }
  score.mssd_average_recall = recall_sum / static_cast<double>(mssd_thresholds.size());
  return score;
}

}  // namespace

std::vector<double> BopMssdThresholds() {
  // As numpy's arange(0.05, 0.51, 0.05) makes them, start + i * step: its 0.3 is 0.3, where
  // 0.05 * 6 would be 0.30000000000000004.
  std::vector<double> thresholds;
  for (int i = 0; i < 10; ++i) thresholds.push_back(0.05 + 0.05 * i);
  return thresholds;
}

StatusOr<ScanScore> ScoreScan(std::span<const PartDefinition> parts, std::span<const TrueInstance> truth,
                              std::span<const EstimatedInstance> estimates, const ScoringOptions& options) {
  std::unordered_map<uint32_t, size_t> part_index;
  RETURN_IF_ERROR(CheckInputs(parts, truth, estimates, options, part_index));
  const std::vector<double> thresholds =
      options.mssd_thresholds.empty() ? BopMssdThresholds() : options.mssd_thresholds;

  ScanScore scan;
  size_t add_correct = 0;
  double mssd_correct = 0;  // recall times valid instances, summed over thresholds
  for (const PartDefinition& part : parts) {
    PartScore score = ScorePart(part, truth, estimates, options, thresholds);
    if (options.cancel != nullptr && options.cancel->load()) return Cancelled("scoring cancelled");
    scan.valid_instances += score.valid_instances;
    add_correct += score.add_correct;
    for (const double r : score.mssd_recalls) mssd_correct += r * static_cast<double>(score.valid_instances);
    scan.parts.push_back(std::move(score));
  }
  if (scan.valid_instances > 0) {
    const auto n = static_cast<double>(scan.valid_instances);
    scan.add_recall = static_cast<double>(add_correct) / n;
    scan.mssd_average_recall = mssd_correct / (n * static_cast<double>(thresholds.size()));
  }
  return scan;
}

}  // namespace vscan::localization
