#include "picking/empty_bin.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include <Eigen/Geometry>

#include "geometry/open_bin_mesh.h"
#include "grasping/grasp_outcome.h"
#include "grasping/gripper_sweep.h"
#include "grasping/sweep_contact.h"

namespace vscan::picking {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Within 10 degrees: cos(10 deg).
constexpr double kRetryCos = 0.984807753;
// The true parts tried for a grasp lie within their radius and this much of the tool.
constexpr double kGraspSearchM = 0.05;

struct Prepared {
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;
  std::vector<double> radii;
  std::vector<std::shared_ptr<const grasping::GraspTarget>> targets;
  std::vector<grasping::ConvexPiece> sweep;
  std::vector<grasping::PlacedMesh> fixtures;  // the bin first
};

StatusOr<Prepared> Prepare(const Cell& cell) {
  if (cell.grasps.size() != cell.types.size()) {
    return InvalidArgument("cell.grasps", "needs one list per part type");
  }
  Prepared out;
  for (const physics::PartType& type : cell.types) {
    out.meshes.push_back(std::make_shared<const TriangleMesh>(type.mesh));
    double radius = 0;
    for (const Eigen::Vector3f& v : type.mesh.vertices) radius = std::max(radius, double(v.norm()));
    out.radii.push_back(radius);
    ASSIGN_OR_RETURN(auto target, grasping::GraspTarget::Make(type.mesh, cell.gripper));
    out.targets.push_back(std::move(target));
  }
  for (const TriangleMesh& piece : grasping::GripperSweep(cell.gripper, cell.pick_options.sweep)) {
    out.sweep.emplace_back(piece);
  }
  const TriangleMesh bin = cell.bin.mesh.empty()
                               ? geometry::OpenBinMesh(cell.bin.inner_size, cell.bin.wall_thickness)
                               : cell.bin.mesh;
  out.fixtures.push_back({std::make_shared<const TriangleMesh>(bin), cell.bin.world_from_bin});
  out.fixtures.insert(out.fixtures.end(), cell.fixtures.begin(), cell.fixtures.end());
  return out;
}

grasping::Pile PileOf(const Prepared& prepared, const std::vector<std::pair<size_t, Pose3>>& parts) {
  grasping::Pile pile;
  for (const auto& [type, pose] : parts) pile.parts.push_back({type, prepared.meshes[type], pose});
  pile.fixtures = prepared.fixtures;
  return pile;
}

bool NearFailed(const Pose3& tool, const std::vector<Pose3>& failed, double distance) {
  return std::any_of(failed.begin(), failed.end(), [&](const Pose3& f) {
    return (f.translation() - tool.translation()).norm() <= distance &&
           f.linear().col(2).dot(tool.linear().col(2)) >= kRetryCos;
  });
}

}  // namespace

const char* StepOutcomeName(StepOutcome outcome) {
  switch (outcome) {
    case StepOutcome::kPicked: return "picked";
    case StepOutcome::kNothingFound: return "nothing_found";
    case StepOutcome::kNothingPickable: return "nothing_pickable";
    case StepOutcome::kCollision: return "collision";
    case StepOutcome::kWrongPose: return "wrong_pose";
  }
  return "unknown";
}

StatusOr<EmptyBinResult> EmptyBin(const Cell& cell, std::vector<physics::PlacedPart> pile, const Perceive& perceive,
                                  const EmptyBinOptions& options, const std::atomic<bool>* cancel,
                                  const std::function<void(const PickStep&, const std::vector<physics::PlacedPart>&)>&
                                      on_step) {
  ASSIGN_OR_RETURN(const Prepared prepared, Prepare(cell));
  for (size_t i = 0; i < pile.size(); ++i) {
    if (pile[i].type >= cell.types.size()) {
      return InvalidArgument("pile[" + std::to_string(i) + "].type", "names no part type");
    }
  }
  const auto cancelled = [cancel] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); };
  EmptyBinResult result;
  std::vector<Pose3> failed_tools;
  size_t failures_in_a_row = 0;
  for (size_t step = 0;; ++step) {
    if (cancelled()) {
      result.end = "cancelled";
      break;
    }
    if (pile.empty()) {
      result.end = "empty";
      break;
    }
    if (step >= options.max_steps) {
      result.end = "step bound";
      break;
    }
    PickStep record;
    record.step = step;
    record.parts_before = pile.size();
    auto start = Clock::now();
    ASSIGN_OR_RETURN(const std::vector<Estimate> estimates, perceive(pile));
    record.perceive_s = Since(start);
    record.estimates = estimates.size();
    std::optional<std::string> end;
    if (estimates.empty()) {
      record.outcome = StepOutcome::kNothingFound;
      record.detail = "the localizer found no part";
      end = "nothing found";
    } else {
      start = Clock::now();
      std::vector<std::pair<size_t, Pose3>> estimated;
      for (size_t e = 0; e < estimates.size(); ++e) {
        if (estimates[e].type >= cell.types.size()) {
          return InvalidArgument("estimates[" + std::to_string(e) + "].type", "names no part type");
        }
        estimated.emplace_back(estimates[e].type, estimates[e].world_from_part);
      }
      ASSIGN_OR_RETURN(const auto verdicts, grasping::CheckPicks(PileOf(prepared, estimated), cell.grasps, cell.gripper,
                                                                 cell.pick_options, cell.reach, cancel));
      std::optional<size_t> chosen;
      std::map<std::string, size_t> why_not;
      for (size_t e = 0; e < verdicts.size(); ++e) {
        if (!verdicts[e].pickable) {
          ++why_not[grasping::PickFailureName(verdicts[e].failure)];
          continue;
        }
        ++record.pickable_estimates;
        if (NearFailed(verdicts[e].world_from_tool, failed_tools, options.retry_distance_m)) continue;
        if (!chosen || estimates[e].score > estimates[*chosen].score) chosen = e;
      }
      record.plan_s = Since(start);
      if (!chosen) {
        record.outcome = StepOutcome::kNothingPickable;
        record.detail = std::to_string(record.pickable_estimates) + " of " + std::to_string(estimates.size()) +
                        " estimates pickable";
        std::string reasons;
        for (const auto& [reason, count] : why_not) {
          reasons += (reasons.empty() ? "" : ", ") + std::to_string(count) + " " + reason;
        }
        if (!reasons.empty()) record.detail += " (" + reasons + ")";
        if (record.pickable_estimates > 0) record.detail += "; those pickable failed before";
        end = "nothing pickable";
      } else {
        const Estimate& estimate = estimates[*chosen];
        const grasping::Grasp& grasp = cell.grasps[estimate.type][*verdicts[*chosen].grasp];
        const Pose3 tool = verdicts[*chosen].world_from_tool;
        record.world_from_tool = tool;
        // The part the grasp closes on where the parts truly lie: the nearest one it holds.
        std::vector<std::pair<double, size_t>> near;
        for (size_t i = 0; i < pile.size(); ++i) {
          const double d = (pile[i].world_from_part.translation() - tool.translation()).norm();
          if (d <= prepared.radii[pile[i].type] + kGraspSearchM) near.emplace_back(d, i);
        }
        std::sort(near.begin(), near.end());
        std::optional<size_t> held;
        for (const auto& [d, i] : near) {
          const Pose3 truth_from_estimate = pile[i].world_from_part.inverse() * estimate.world_from_part;
          if (prepared.targets[pile[i].type]->Try(grasp, truth_from_estimate).holds) {
            held = i;
            break;
          }
        }
        std::vector<std::pair<size_t, Pose3>> truth;
        for (const physics::PlacedPart& part : pile) truth.emplace_back(part.type, part.world_from_part);
        const auto contact = grasping::FindSweepContact(PileOf(prepared, truth),
                                                        held.value_or(std::numeric_limits<size_t>::max()),
                                                        prepared.sweep, tool);
        if (contact) {
          record.outcome = StepOutcome::kCollision;
          record.detail = "the gripper's way in meets " + grasping::Describe(*contact) + " where it truly lies";
        } else if (!held) {
          record.outcome = StepOutcome::kWrongPose;
          record.detail = "the grasp planned on the estimate holds no part where the parts truly lie";
        } else {
          record.outcome = StepOutcome::kPicked;
          record.picked = pile[*held];
          pile.erase(pile.begin() + std::ptrdiff_t(*held));
          ++result.picked;
          start = Clock::now();
          if (!pile.empty()) {
            ASSIGN_OR_RETURN(const physics::FillResult settled,
                             physics::SettlePile(cell.bin, cell.types, pile, cell.physics, cancel));
            pile = settled.parts;
            record.fell_out = settled.outside.size();
            result.fell_out += settled.outside.size();
          }
          record.settle_s = Since(start);
        }
        if (record.outcome == StepOutcome::kPicked) {
          failures_in_a_row = 0;
        } else {
          failed_tools.push_back(tool);
          if (++failures_in_a_row >= options.max_failures_in_a_row) end = "failures in a row";
        }
      }
    }
    result.steps.push_back(record);
    if (on_step) on_step(record, pile);
    if (end) {
      result.end = *end;
      break;
    }
  }
  result.pile = std::move(pile);
  return result;
}

}  // namespace vscan::picking
