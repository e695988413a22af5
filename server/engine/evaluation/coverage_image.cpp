#include "evaluation/coverage_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "spatial/kd_tree.h"
#include "vscan/common/png_codec.h"

namespace vscan::evaluation {
namespace {

constexpr int kMinPanel = 16;
constexpr int kMaxPanel = 2048;
// Empty border around the drawing in each panel, as a share of the panel's side.
constexpr float kMargin = 0.05f;
constexpr std::array<uint8_t, 3> kUncovered{215, 25, 25};
constexpr float kNearGrey = 225, kFarGrey = 70;
// Splat sides, in pixels.
constexpr int kMinSplat = 2, kMaxSplat = 16;
// Samples whose nearest-neighbour distance sets the splat size.
constexpr size_t kSpacingProbes = 4096;

// One panel's view: screen x along right, screen y against up, looking along forward.
struct PanelView {
  Eigen::Vector3f right;
  Eigen::Vector3f up;
  Eigen::Vector3f forward;
};

// Front, right, back and left: each view a quarter turn about up from the one before. The front
// looks along +y (or -z, or +x when up is close to those).
std::array<PanelView, 4> PanelViews(const Eigen::Vector3f& up) {
  Eigen::Vector3f forward = Eigen::Vector3f::UnitX();
  for (const Eigen::Vector3f& axis : {Eigen::Vector3f(0, 1, 0), Eigen::Vector3f(0, 0, -1)}) {
    if (std::abs(axis.dot(up)) < 0.9f) {
      forward = axis;
      break;
    }
  }
  forward = (forward - forward.dot(up) * up).normalized();
  std::array<PanelView, 4> views;
  for (PanelView& view : views) {
    view = {forward.cross(up), up, forward};
    forward = up.cross(forward);
  }
  return views;
}

// Where the samples sit about up: the centre of their bounds, the largest distance from the up
// axis through it, and their extent along up.
struct Framing {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  float radius = 0;
  float up_low = 0, up_high = 0;
};

Framing FrameSamples(std::span<const Eigen::Vector3f> samples, const Eigen::Vector3f& up) {
  Framing f;
  if (samples.empty()) return f;
  Eigen::Vector3f lo = samples[0], hi = samples[0];
  for (const Eigen::Vector3f& p : samples) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  f.centre = (lo + hi) / 2;
  f.up_low = std::numeric_limits<float>::infinity();
  f.up_high = -f.up_low;
  for (const Eigen::Vector3f& p : samples) {
    const Eigen::Vector3f d = p - f.centre;
    const float along = d.dot(up);
    f.radius = std::max(f.radius, (d - along * up).norm());
    f.up_low = std::min(f.up_low, along);
    f.up_high = std::max(f.up_high, along);
  }
  return f;
}

// The typical distance between neighbouring samples: for points spread uniformly by area with
// density rho the median nearest-neighbour distance is sqrt(ln 2 / (pi rho)), so 1 / sqrt(rho) is
// about 2.13 times it. 0 with fewer than two samples.
float SampleSpacing(std::span<const Eigen::Vector3f> samples) {
  if (samples.size() < 2) return 0;
  const spatial::KdTree tree(samples);
  const size_t step = std::max<size_t>(1, samples.size() / kSpacingProbes);
  std::vector<float> nearest;
  spatial::Neighbor two[2];
  for (size_t i = 0; i < samples.size(); i += step) {
    if (tree.Knn(samples[i], std::numeric_limits<float>::infinity(), two) == 2) nearest.push_back(two[1].dist_sq);
  }
  const auto middle = nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2);
  std::nth_element(nearest.begin(), middle, nearest.end());
  return 2.13f * std::sqrt(*middle);
}

// Squares of side s leave a share exp(-s^2 / spacing^2) of a surface bare where it faces the
// viewer: 2.6 spacings leave about one pixel in a thousand, so that hidden samples rarely show
// through the gaps of nearer ones.
int SplatSide(float spacing_px) {
  return std::clamp(static_cast<int>(std::ceil(2.6f * spacing_px)), kMinSplat, kMaxSplat);
}

class Canvas {
 public:
  explicit Canvas(int panel)
      : panel_(panel), side_(2 * panel), rgb_(size_t(side_) * side_ * 3, 255),
        depth_(size_t(side_) * side_, std::numeric_limits<float>::infinity()) {}

  // A square splat of the given side with its centre at (x, y) in panel k, kept where nearer.
  void Splat(int k, float x, float y, int side, float depth, const std::array<uint8_t, 3>& colour) {
    const int x0 = static_cast<int>(std::floor(x - side / 2.0f + 0.5f));
    const int y0 = static_cast<int>(std::floor(y - side / 2.0f + 0.5f));
    const int left = (k % 2) * panel_, top = (k / 2) * panel_;
    for (int py = std::max(y0, 0); py < std::min(y0 + side, panel_); ++py) {
      for (int px = std::max(x0, 0); px < std::min(x0 + side, panel_); ++px) {
        const size_t at = size_t(top + py) * side_ + size_t(left + px);
        if (!(depth < depth_[at])) continue;
        depth_[at] = depth;
        std::copy(colour.begin(), colour.end(), rgb_.begin() + static_cast<std::ptrdiff_t>(3 * at));
      }
    }
  }

  int side() const { return side_; }
  const std::vector<uint8_t>& rgb() const { return rgb_; }

 private:
  int panel_;
  int side_;
  std::vector<uint8_t> rgb_;
  std::vector<float> depth_;
};

Status Validate(std::span<const Eigen::Vector3f> samples, std::span<const uint8_t> covered,
                const CoverageImageOptions& options) {
  if (covered.size() != samples.size()) {
    return InvalidArgument("covered", "must have one entry per sample (" + std::to_string(covered.size()) + " for " +
                                          std::to_string(samples.size()) + " samples)");
  }
  if (options.panel_size < kMinPanel || options.panel_size > kMaxPanel) {
    return InvalidArgument("coverage_image.panel_size",
                           "must be between " + std::to_string(kMinPanel) + " and " + std::to_string(kMaxPanel));
  }
  if (!options.up.allFinite() || !(options.up.norm() > 1e-6f)) {
    return InvalidArgument("coverage_image.up", "must be finite and not zero");
  }
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].allFinite()) return InvalidArgument("samples[" + std::to_string(i) + "]", "NaN or infinite");
  }
  return Status::Ok();
}

}  // namespace

StatusOr<std::string> RenderCoveragePng(std::span<const Eigen::Vector3f> samples, std::span<const uint8_t> covered,
                                        const CoverageImageOptions& options) {
  RETURN_IF_ERROR(Validate(samples, covered, options));
  const Eigen::Vector3f up = options.up.normalized();
  const Framing framing = FrameSamples(samples, up);
  const int panel = options.panel_size;
  // One scale for every panel, so that the four sides compare.
  const float extent = std::max({2 * framing.radius, framing.up_high - framing.up_low, 1e-9f});
  const float scale = panel * (1 - 2 * kMargin) / extent;
  const float up_middle = (framing.up_low + framing.up_high) / 2;
  const float depth_span = std::max(2 * framing.radius, 1e-9f);
  const int splat = SplatSide(SampleSpacing(samples) * scale);

  Canvas canvas(panel);
  const std::array<PanelView, 4> views = PanelViews(up);
  for (int k = 0; k < 4; ++k) {
    const PanelView& view = views[static_cast<size_t>(k)];
    for (size_t i = 0; i < samples.size(); ++i) {
      const Eigen::Vector3f d = samples[i] - framing.centre;
      const float x = panel / 2.0f + d.dot(view.right) * scale;
      const float y = panel / 2.0f - (d.dot(view.up) - up_middle) * scale;
      const float depth = d.dot(view.forward);
      std::array<uint8_t, 3> colour = kUncovered;
      if (covered[i] != 0) {
        // Nearer is lighter.
        const float t = std::clamp((depth + framing.radius) / depth_span, 0.0f, 1.0f);
        const auto grey = static_cast<uint8_t>(std::lround(kNearGrey + t * (kFarGrey - kNearGrey)));
        colour = {grey, grey, grey};
      }
      canvas.Splat(k, x, y, splat, depth, colour);
    }
  }
  const auto side = static_cast<uint32_t>(canvas.side());
  return EncodePng(side, side, canvas.rgb());
}

}  // namespace vscan::evaluation
