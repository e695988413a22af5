// The TRAC-IK protocol on the fixture robots: random reachable poses (q uniform within the
// limits, continuous joints in [-pi, pi], FK -> target), solved from the middle of the limits,
// 5 ms budget per solve. Success, for every solver alike: the returned joints lie within the
// limits and their FK (ours) is within 1e-5 m (|p_target - p|) and 1e-5 rad (angle of
// R_target^T R) of the target. Times are wall-clock per solve call.
//
// Usage: ik_bench [--poses=N] [--gd-poses=N] [--no-kdl-restarts]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <urdf_model/model.h>

#include "ik_bench_kdl.h"
#include "robot/forward_kinematics.h"
#include "robot/ik_gradient_descent.h"
#include "robot/ik_solver.h"
#include "robot/urdf_bundle.h"
#include "robot/urdf_chain.h"

namespace vscan::bench {
namespace {

using robot::KinematicChain;

constexpr uint64_t kPoseSeed = 42;
constexpr double kTolerance = 1e-5;
constexpr std::chrono::microseconds kBudget{5000};

struct Robot {
  const char* name;
  const char* urdf;
  const char* base;
  const char* tip;
};

struct Outcome {
  double ms = 0.0;
  bool success = false;
};

// Solves target from seed into q; returns whether the solver claims success (not trusted).
using Solver = std::function<void(const Pose3& target, const Eigen::VectorXd& seed, Eigen::VectorXd* q)>;

robot::UrdfBundle LoadBundle(const Robot& r) {
  const std::filesystem::path root = std::filesystem::path(VSCAN_DATA_DIR) / "robots" / r.name;
  std::vector<robot::BundleFile> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    files.push_back({std::filesystem::relative(entry.path(), root).generic_string(), bytes.str()});
  }
  StatusOr<robot::UrdfBundle> bundle = robot::LoadUrdfBundle(r.urdf, std::move(files));
  if (!bundle.ok()) {
    std::fprintf(stderr, "%s: %s\n", r.name, bundle.status().ToString().c_str());
    std::exit(1);
  }
  return std::move(bundle).value();
}

bool Reached(const KinematicChain& chain, const Pose3& target, const Eigen::VectorXd& q) {
  StatusOr<Pose3> achieved = robot::ForwardKinematics(chain, q);
  if (!achieved.ok()) return false;
  const robot::GoalErrors errors = robot::MeasureGoalErrors(robot::PoseGoal(target), *achieved);
  return errors.position <= kTolerance && errors.orientation <= kTolerance;
}

std::vector<Outcome> Run(const KinematicChain& chain, const std::vector<Pose3>& targets, size_t count,
                         const Solver& solve) {
  const Eigen::VectorXd seed = chain.MidLimits();
  std::vector<Outcome> outcomes;
  Eigen::VectorXd q = seed;
  for (size_t i = 0; i < std::min(count, targets.size()); ++i) {
    const auto start = std::chrono::steady_clock::now();
    solve(targets[i], seed, &q);
    const auto stop = std::chrono::steady_clock::now();
    outcomes.push_back({std::chrono::duration<double, std::milli>(stop - start).count(), Reached(chain, targets[i], q)});
  }
  return outcomes;
}

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

void PrintRow(const char* robot, const char* solver, const std::vector<Outcome>& outcomes) {
  if (outcomes.empty()) return;
  std::vector<double> all, ok;
  for (const Outcome& o : outcomes) {
    all.push_back(o.ms);
    if (o.success) ok.push_back(o.ms);
  }
  std::printf("| %-6s | %-40s | %6zu | %7.2f%% | %8.4f | %8.4f | %8.4f | %8.4f |\n", robot, solver, outcomes.size(),
              100.0 * static_cast<double>(ok.size()) / static_cast<double>(outcomes.size()), Mean(ok), Median(ok),
              Mean(all), Median(all));
  std::fflush(stdout);
}

size_t ArgValue(int argc, char** argv, const char* name, size_t fallback) {
  const size_t len = std::strlen(name);
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], name, len) == 0 && argv[i][len] == '=') return std::stoul(argv[i] + len + 1);
  }
  return fallback;
}

bool HasFlag(int argc, char** argv, const char* name) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], name) == 0) return true;
  }
  return false;
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  using namespace vscan;
  using namespace vscan::bench;
  const size_t poses = ArgValue(argc, argv, "--poses", 10000);
  const size_t gd_poses = ArgValue(argc, argv, "--gd-poses", 1000);
  const bool kdl_restarts = !HasFlag(argc, argv, "--no-kdl-restarts");
  std::printf("IK, TRAC-IK protocol: pose seed %llu, tolerance %g m and %g rad, budget %lld us, seed = mid-limits\n",
              static_cast<unsigned long long>(kPoseSeed), kTolerance, kTolerance,
              static_cast<long long>(kBudget.count()));
  std::printf("| robot  | solver                                   | poses  | success  | ok mean  | ok med   | all mean | all med  |\n");
  std::printf("|--------|------------------------------------------|--------|----------|----------|----------|----------|----------|\n");
  const Robot robots[] = {{"ur5", "ur5_robot.urdf", "base_link", "tool0"},
                          {"panda", "panda.urdf", "panda_link0", "panda_link8"}};
  for (const Robot& r : robots) {
    const robot::UrdfBundle bundle = LoadBundle(r);
    const KinematicChain chain = robot::BuildChain(*bundle.model, {r.base, r.tip}).value();
    std::mt19937_64 rng(kPoseSeed);
    std::vector<Pose3> targets;
    for (size_t i = 0; i < poses; ++i) {
      targets.push_back(robot::ForwardKinematics(chain, robot::RandomJointPositions(chain, rng)).value());
    }
    robot::IkOptions options;
    options.time_budget = kBudget;
    PrintRow(r.name, "vscan SolveIk (LM + restarts)", Run(chain, targets, poses, [&](const Pose3& t, const Eigen::VectorXd& s, Eigen::VectorXd* q) {
      robot::IkResult nearest;
      StatusOr<robot::IkResult> result = robot::SolveIk(chain, robot::PoseGoal(t), s, options, &nearest);
      *q = result.ok() ? result->joint_positions : nearest.joint_positions;
    }));
    robot::GradientDescentOptions gd;
    gd.time_budget = kBudget;
    PrintRow(r.name, "vscan gradient descent (paper)", Run(chain, targets, gd_poses, [&](const Pose3& t, const Eigen::VectorXd& s, Eigen::VectorXd* q) {
      robot::IkResult nearest;
      StatusOr<robot::IkResult> result = robot::SolveIkGradientDescent(chain, robot::PoseGoal(t), s, gd, &nearest);
      *q = result.ok() ? result->joint_positions : nearest.joint_positions;
    }));
    KdlIk kdl(*bundle.model, r.base, r.tip, 100, kTolerance);
    PrintRow(r.name, "KDL NR_JL (100 it, eps 1e-5, 1 attempt)", Run(chain, targets, poses, [&](const Pose3& t, const Eigen::VectorXd& s, Eigen::VectorXd* q) {
      kdl.Solve(t, s, q);
    }));
    if (kdl_restarts) {
      PrintRow(r.name, "KDL NR_JL + random restarts to 5 ms", Run(chain, targets, poses, [&](const Pose3& t, const Eigen::VectorXd& s, Eigen::VectorXd* q) {
        kdl.SolveWithRestarts(t, s, kBudget, q);
      }));
    }
  }
  std::printf("times in ms; 'ok' columns over successful solves, 'all' over every solve\n");
  return 0;
}
