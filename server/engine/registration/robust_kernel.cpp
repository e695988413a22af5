#include "registration/robust_kernel.h"

#include <algorithm>

namespace vscan::registration {

const char* RobustKernelName(RobustKernel kernel) {
  switch (kernel) {
    case RobustKernel::kHuber:
      return "huber";
    case RobustKernel::kTukey:
      return "tukey";
    case RobustKernel::kNone:
      break;
  }
  return "none";
}

double KernelWidth(RobustKernel kernel, double requested) {
  if (requested > 0.0) return requested;
  switch (kernel) {
    case RobustKernel::kHuber:
      return 1.345;
    case RobustKernel::kTukey:
      return 4.685;
    case RobustKernel::kNone:
      break;
  }
  return 1.0;
}

double Median(std::span<float> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return static_cast<double>(*mid);
}

double MadScale(std::span<float> abs_values) { return 1.4826 * Median(abs_values); }

}  // namespace vscan::registration
