#pragma once
// Robust weights for residuals, scaled by a robust estimate of the residuals' spread.

#include <span>

namespace vscan::registration {

enum class RobustKernel { kNone, kHuber, kTukey };

const char* RobustKernelName(RobustKernel kernel);

// `requested` when positive, else the kernel's usual width in scales (95% efficiency on Gaussian
// residuals): 1.345 for Huber, 4.685 for Tukey.
double KernelWidth(RobustKernel kernel, double requested);

// The weight of residual r under a kernel of width c (metres): 1 near zero, falling for Huber,
// reaching 0 at |r| >= c for Tukey.
inline double RobustWeight(RobustKernel kernel, double r, double c) {
  switch (kernel) {
    case RobustKernel::kHuber: {
      const double a = r < 0 ? -r : r;
      return a <= c ? 1.0 : c / a;
    }
    case RobustKernel::kTukey: {
      if (r >= c || r <= -c) return 0.0;
      const double u = r / c;
      const double v = 1.0 - u * u;
      return v * v;
    }
    case RobustKernel::kNone:
      break;
  }
  return 1.0;
}

// The median (the upper one for an even count); reorders `values`; 0 when empty.
double Median(std::span<float> values);

// 1.4826 times the median of the absolute values, the Gaussian sigma of zero-centred residuals
// (the median absolute deviation about zero). Reorders `abs_values`; 0 when empty.
double MadScale(std::span<float> abs_values);

}  // namespace vscan::registration
