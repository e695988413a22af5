#include "service/model/model_next_best_views.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "evaluation/next_best_views.h"
#include "robot/ik_types.h"
#include "robot_registry/arm_kinematics.h"
#include "service/model/model_frame.h"

namespace vscan::service {
namespace {

constexpr double kElevationsDeg[] = {0, 20, 40, 60};
constexpr double kAzimuthStepDeg = 30;
constexpr double kTableStepDeg = 45;
constexpr std::chrono::milliseconds kIkBudget{50};
constexpr double kIkTolerance = 1e-4;
constexpr size_t kRaysPerCandidate = 50'000;

struct RingPoint {
  Eigen::Vector3d eye;  // world frame
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

struct Candidate {
  Eigen::Vector3d eye;     // world
  Eigen::Vector3d target;  // world
  double angle = 0;        // the table's
};

}  // namespace

StatusOr<ProposedViews> ProposeNextBestViews(robot_registry::RobotRegistry& robots, const NextBestViewRequest& request,
                                             const std::atomic<bool>* cancel) {
  ProposedViews out;
  const double distance = MedianDistance(request.scan_poses, request.centre);
  if (!(distance > 0)) {
    out.note = "no aligned scan to take the viewing distance from";
    return out;
  }
  ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, robots.Mount(request.mount_id));
  robot_registry::IkSettings settings;
  settings.position_tolerance = kIkTolerance;
  settings.orientation_tolerance = kIkTolerance;
  settings.time_budget = kIkBudget;

  const bool table = request.table && request.table->enabled;
  const Eigen::Vector3d up = table ? request.table->axis.normalized() : Eigen::Vector3d::UnitZ();
  // With a table the views aim at its axis at the object's height: one ring in the world then
  // serves every table angle (the arm does not turn with the table), so each viewpoint is solved
  // once rather than once per angle, which an unreachable one would pay its whole IK budget for.
  const Eigen::Vector3d aim =
      table ? request.table->centre + (request.centre - request.table->centre).dot(up) * up : request.centre;
  const std::vector<RingPoint> ring = Ring(aim, up, distance);
  std::vector<Pose3> reached;
  std::vector<Eigen::Vector3d> eyes;
  for (const RingPoint& point : ring) {
    if (cancel && cancel->load()) return Cancelled("model job stopped");
    ASSIGN_OR_RETURN(const robot::IkGoal goal, robot::LookAtGoal(point.eye, aim, "next_best_view"));
    ASSIGN_OR_RETURN(const robot_registry::IkAnswer answer,
                     robot_registry::SolveInPlacement(*mounted.chain, mounted.placement, goal, {}, settings));
    if (!answer.reached) continue;
    reached.push_back(answer.frame_from_tool);
    eyes.push_back(point.eye);
  }
  std::vector<evaluation::CandidateView> views;
  std::vector<Candidate> candidates;
  for (double angle = 0; angle < (table ? 360 : 1); angle += kTableStepDeg) {
    const Pose3 model_from_world = WorldFromModel(request.table, angle).inverse();
    for (size_t i = 0; i < reached.size(); ++i) {
      evaluation::CandidateView view;
      view.frame_from_sensor = model_from_world * reached[i];
      view.tag = static_cast<uint32_t>(candidates.size());
      views.push_back(view);
      candidates.push_back({eyes[i], aim, angle});
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
  options.light = request.light;
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
