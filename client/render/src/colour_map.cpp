#include "vscan/render/colour_map.h"

#include <algorithm>
#include <cmath>

namespace vscan::render {

Eigen::Vector3f Turbo(float t) {
  const float x = std::clamp(t, 0.0f, 1.0f);
  // Degree-5 polynomial per channel, coefficients of 1, x, x^2, x^3, x^4, x^5.
  static constexpr float kRed[6] = {0.13572138f, 4.61539260f, -42.66032258f, 132.13108234f, -152.94239396f,
                                    59.28637943f};
  static constexpr float kGreen[6] = {0.09140261f, 2.19418839f, 4.84296658f, -14.18503333f, 4.27729857f,
                                      2.82956604f};
  static constexpr float kBlue[6] = {0.10667330f, 12.64194608f, -60.58204836f, 110.36276771f, -89.90310912f,
                                     27.34824973f};
  const auto poly = [x](const float (&c)[6]) {
    float v = c[5];
    for (int i = 4; i >= 0; --i) v = v * x + c[i];
    return std::clamp(v, 0.0f, 1.0f);
  };
  return {poly(kRed), poly(kGreen), poly(kBlue)};
}

Eigen::Vector3f InstanceColour(uint32_t id) {
  if (id == 0) return Eigen::Vector3f::Constant(kInstanceZeroGrey);
  constexpr double kGoldenRatioConjugate = 0.6180339887498949;
  const double hue = std::fmod(0.1 + id * kGoldenRatioConjugate, 1.0) * 6.0;
  // Alternating value keeps ids whose hues nearly repeat (every 21st, 34th, ...) apart.
  const float value = (id / 7) % 2 == 0 ? 0.95f : 0.7f;
  const float saturation = 0.75f;
  const int sector = static_cast<int>(hue);
  const float f = static_cast<float>(hue - sector);
  const float p = value * (1 - saturation);
  const float q = value * (1 - saturation * f);
  const float r = value * (1 - saturation * (1 - f));
  switch (sector) {
    case 0: return {value, r, p};
    case 1: return {q, value, p};
    case 2: return {p, value, r};
    case 3: return {p, q, value};
    case 4: return {r, p, value};
    default: return {value, p, q};
  }
}

}  // namespace vscan::render
