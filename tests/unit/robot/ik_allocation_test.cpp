// The solvers' inner loops must not allocate: a solve that takes thousands of iterations and
// restarts allocates exactly as often as one that converges at once.

#include <atomic>
#include <cstddef>

#include <gtest/gtest.h>

#include "robot/forward_kinematics.h"
#include "robot/ik_gradient_descent.h"
#include "robot/ik_solver.h"
#include "robot/reach.h"
#include "robot_fixtures.h"

// Counts every malloc in the process: operator new and Eigen's allocator both end up here.
namespace {
std::atomic<long> g_allocations{0};
}  // namespace

extern "C" void* __libc_malloc(std::size_t size);  // glibc's own allocator
extern "C" void* malloc(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}

namespace vscan::robot {
namespace {

template <typename Solve>
long AllocationsOf(Solve&& solve) {
  const long before = g_allocations.load();
  solve();
  return g_allocations.load() - before;
}

TEST(IkAllocation, InnerLoopsDoNotAllocate) {
  const KinematicChain chain = testing::FixtureChain("ur5");
  const Eigen::VectorXd seed = chain.MidLimits();
  const IkGoal easy = PoseGoal(ForwardKinematics(chain, seed).value());
  // Within the crude reach bound but beyond the true reach: runs until the budget ends.
  const double distance = 0.5 * (SampledReach(chain, 2000, 1) + ReachUpperBound(chain));
  const IkGoal hard = PositionGoal(FirstJointOrigin(chain) + distance * Eigen::Vector3d::UnitX());

  IkOptions options;
  options.time_budget = std::chrono::microseconds(20000);
  IkResult easy_result, hard_result;
  const long easy_count = AllocationsOf([&] { easy_result = SolveIk(chain, easy, seed, options).value(); });
  const long hard_count = AllocationsOf([&] { (void)SolveIk(chain, hard, seed, options, &hard_result); });
  EXPECT_EQ(easy_result.iterations, 0);
  EXPECT_GT(hard_result.iterations, 1000);
  EXPECT_GT(hard_result.restarts, 5);
  // The failure adds its message; everything else is per call, not per iteration.
  EXPECT_LE(hard_count, easy_count + 8) << easy_count << " vs " << hard_count;

  GradientDescentOptions gd;
  gd.max_sweeps = 3000;
  gd.time_budget = std::chrono::microseconds(10'000'000);
  IkResult gd_hard;
  const long gd_easy_count = AllocationsOf([&] { (void)SolveIkGradientDescent(chain, easy, seed, gd); });
  const long gd_hard_count = AllocationsOf([&] { (void)SolveIkGradientDescent(chain, hard, seed, gd, &gd_hard); });
  EXPECT_GT(gd_hard.iterations, 100);
  EXPECT_LE(gd_hard_count, gd_easy_count + 8) << gd_easy_count << " vs " << gd_hard_count;
}

}  // namespace
}  // namespace vscan::robot
