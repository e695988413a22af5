#include "service/model_next_best_views.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <tuple>

#include "evaluation/next_best_views.h"
#include "robot/ik_types.h"
#include "robots/arm_kinematics.h"
#include "service/model_frame.h"

namespace vscan::service {
namespace {

constexpr double kElevationsDeg[] = {0, 20, 40, 60};
constexpr double kAzimuthStepDeg = 30;
constexpr double kTableStepDeg = 45;
constexpr std::chrono::milliseconds kIkBudget{50};
constexpr double kIkTolerance = 1e-4;
constexpr size_t kRaysPerCandidate = 50'000;

struct RingPoint {
  Eigen::Vector3d eye;  // model frame
};

std::vector<RingPoint> Ring(const Eigen::Vector3d& centre, const Eigen::Vector3d& up, double distance) {
  const Eigen::Vector3d u = up.normalized();
  const Eigen::Vector3d e1 = u.unitOrthogonal();
  const Eigen::Vector3d e2 = u.cross(e1);
  std::vector<RingPoint> ring;
  for (const double elevation : kElevationsDeg) {
    const double el = DegreesToRadians(elevation);
    for (double azimuth = 0; azimuth < 360; azimuth += kAzimuthStepDeg) {
      const double az = DegreesToRadians(azimuth);
      const Eigen::Vector3d direction = std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) + std::sin(el) * u;
      ring.push_back({centre + distance * direction});
    }
  }
  return ring;
}

double MedianDistance(const std::vector<Pose3>& poses, const Eigen::Vector3d& centre) {
  std::vector<double> d;
  for (const Pose3& pose : poses) d.push_back((pose.translation() - centre).norm());
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

using PointKey = std::tuple<long long, long long, long long>;
PointKey Key(const Eigen::Vector3d& p) {
  return {std::llround(p.x() * 1e6), std::llround(p.y() * 1e6), std::llround(p.z() * 1e6)};
}

struct Candidate {
  Eigen::Vector3d eye;     // world, table at angle
  Eigen::Vector3d target;  // world, table at angle
  double angle = 0;
};

}  // namespace

StatusOr<ProposedViews> ProposeNextBestViews(ServiceContext& context, const NextBestViewRequest& request,
                                             const std::atomic<bool>* cancel) {
  ProposedViews out;
  const double distance = MedianDistance(request.scan_poses, request.centre);
  if (!(distance > 0)) {
    out.note = "no aligned scan to take the viewing distance from";
    return out;
  }
  ASSIGN_OR_RETURN(const robots::MountedRobot mounted, context.robots.Mount(request.mount_id));
  robots::IkSettings settings;
  settings.position_tolerance = kIkTolerance;
  settings.orientation_tolerance = kIkTolerance;
  settings.time_budget = kIkBudget;

  const bool table = request.table && request.table->enabled;
  const Eigen::Vector3d up = table ? request.table->axis : Eigen::Vector3d::UnitZ();
  const std::vector<RingPoint> ring = Ring(request.centre, up, distance);
  // The arm does not turn with the table: a world viewpoint is solved once, whatever the angle.
  std::map<std::pair<PointKey, PointKey>, std::optional<Pose3>> solved;
  std::vector<evaluation::CandidateView> views;
  std::vector<Candidate> candidates;
  for (double angle = 0; angle < (table ? 360 : 1); angle += kTableStepDeg) {
    const Pose3 world_from_model = WorldFromModel(request.table, angle);
    const Eigen::Vector3d target = world_from_model * request.centre;
    for (const RingPoint& point : ring) {
      if (cancel && cancel->load()) return Cancelled("model job stopped");
      const Eigen::Vector3d eye = world_from_model * point.eye;
      auto [it, fresh] = solved.try_emplace({Key(eye), Key(target)});
      if (fresh) {
        ASSIGN_OR_RETURN(const robot::IkGoal goal, robot::LookAtGoal(eye, target, "next_best_view"));
        ASSIGN_OR_RETURN(const robots::IkAnswer answer,
                         robots::SolveInPlacement(*mounted.chain, mounted.placement, goal, {}, settings));
        if (answer.reached) it->second = answer.frame_from_tool;
      }
      if (!it->second) continue;
      evaluation::CandidateView view;
      view.frame_from_sensor = world_from_model.inverse() * *it->second;
      view.tag = static_cast<uint32_t>(candidates.size());
      views.push_back(view);
      candidates.push_back({eye, target, angle});
    }
  }
  out.candidates = candidates.size();
  if (candidates.empty()) {
    out.note = "the arm reaches none of the " + std::to_string(ring.size()) + " viewpoints about the object";
    return out;
  }
  evaluation::NextBestViewOptions options;
  options.max_views = request.count;
  options.tau = request.tau;
  options.max_rays_per_view = kRaysPerCandidate;
  ASSIGN_OR_RETURN(const std::vector<evaluation::ViewPick> picks,
                   evaluation::PickNextBestViews(*request.truth, request.samples, request.covered, request.camera,
                                                 views, options, cancel));
  const double samples = static_cast<double>(std::max<size_t>(1, request.samples.size()));
  for (const evaluation::ViewPick& pick : picks) {
    const Candidate& c = candidates.at(pick.candidate);
    NextBestViewReport view;
    view.position = c.eye;
    view.target = c.target;
    view.table_angle_deg = c.angle;
    view.coverage_gain = static_cast<double>(pick.gained_samples) / samples;
    view.coverage_after = pick.coverage_after;
    out.views.push_back(view);
  }
  if (out.views.empty()) out.note = "no reachable viewpoint would see more of the object";
  return out;
}

}  // namespace vscan::service
