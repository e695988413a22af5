#include "registration/robust_kernel.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace vscan::registration {
namespace {

TEST(RobustKernelTest, WeightsFollowTheirDefinitions) {
  EXPECT_EQ(RobustWeight(RobustKernel::kNone, 123.0, 1.0), 1.0);
  EXPECT_EQ(RobustWeight(RobustKernel::kHuber, 0.5, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(RobustWeight(RobustKernel::kHuber, -4.0, 1.0), 0.25);
  EXPECT_EQ(RobustWeight(RobustKernel::kTukey, 0.0, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(RobustWeight(RobustKernel::kTukey, 1.0, 2.0), 0.5625);
  EXPECT_DOUBLE_EQ(RobustWeight(RobustKernel::kTukey, -1.0, 2.0), 0.5625);
  EXPECT_EQ(RobustWeight(RobustKernel::kTukey, 2.0, 2.0), 0.0);
  EXPECT_EQ(RobustWeight(RobustKernel::kTukey, -7.0, 2.0), 0.0);
}

TEST(RobustKernelTest, WidthsDefaultToTheUsualConstants) {
  EXPECT_EQ(KernelWidth(RobustKernel::kHuber, 0.0), 1.345);
  EXPECT_EQ(KernelWidth(RobustKernel::kTukey, 0.0), 4.685);
  EXPECT_EQ(KernelWidth(RobustKernel::kTukey, 3.0), 3.0);
}

TEST(RobustKernelTest, MadScaleEstimatesGaussianSigmaDespiteOutliers) {
  std::mt19937 rng(1);
  std::normal_distribution<float> g(0.0f, 0.002f);
  std::vector<float> abs_values;
  for (int i = 0; i < 20000; ++i) abs_values.push_back(std::abs(g(rng)));
  // A tenth as many again, far out: they only move the median up to the 55% quantile (1.12 sigma).
  for (int i = 0; i < 2000; ++i) abs_values.push_back(1.0f);
  EXPECT_NEAR(MadScale(abs_values), 0.002, 0.0003);
  EXPECT_EQ(MadScale({}), 0.0);
  std::vector<float> values{5.0f, 1.0f, 3.0f};
  EXPECT_EQ(Median(values), 3.0);
}

}  // namespace
}  // namespace vscan::registration
