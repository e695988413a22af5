#include "localization/ppf_voting.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vscan::localization {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
// Spreads a packed key's bits over the table's slots (the finaliser of MurmurHash3).
uint64_t MixKey(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdULL;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ULL;
  return k ^ (k >> 33);
}

// Rim pairs' keys have the top bit set; a surface pair's distance bin stays below 2^15.
constexpr uint64_t kRimKeyFlag = uint64_t{1} << 63;

// The rigid transform that moves p to the origin and turns n onto +x.
Eigen::Isometry3f LocalFrame(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  Eigen::Isometry3f frame = Eigen::Isometry3f::Identity();
  frame.linear() = Eigen::Quaternionf::FromTwoVectors(n, Eigen::Vector3f::UnitX()).toRotationMatrix();
  frame.translation() = -(frame.linear() * p);
  return frame;
}

// The angle of q (in a reference's local frame) about +x, measured from +y, in 2^-16 turns: the
// difference of two wraps round by itself.
uint16_t AlphaOf(const Eigen::Vector3f& q) {
  const float turns = std::atan2(q.z(), q.y()) / static_cast<float>(kTwoPi);
  return static_cast<uint16_t>(static_cast<int32_t>(std::lround(turns * 65536.0f)) & 0xffff);
}

struct ReferenceVote {
  Pose3 pose = Pose3::Identity();
  uint32_t votes = 0;
};

double RotationAngle(const Pose3& a, const Pose3& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace

PpfModel::PpfModel(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                   std::span<const Eigen::Vector3f> rims, const PpfSettings& settings)
    : settings_(settings), points_(points.begin(), points.end()), normals_(normals.begin(), normals.end()),
      alpha_bins_(static_cast<uint32_t>(std::ceil(kTwoPi / settings.angle_step_rad))) {
  for (size_t i = 0; i < points_.size(); ++i) {
    for (size_t j = i + 1; j < points_.size(); ++j) max_distance_ = std::max(max_distance_, (points_[j] - points_[i]).norm());
  }
  for (size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Isometry3f frame = LocalFrame(points_[i], normals_[i]);
    for (size_t j = 0; j < points_.size(); ++j) {
      if (i == j) continue;
      const uint16_t alpha = AlphaOf(frame * points_[j]);
      const auto slot = static_cast<uint32_t>(i) * alpha_bins_;
      if (const auto key = Key(points_[i], normals_[i], points_[j], normals_[j])) {
        entries_.push_back({*key, slot, alpha});
      }
      if (rims.empty() || rims[j].isZero()) continue;
      if (const auto key = RimKey(points_[i], normals_[i], points_[j], normals_[j], rims[j])) {
        entries_.push_back({*key, slot, alpha});
      }
    }
  }
  std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
  size_t keys = 0;
  for (size_t e = 0; e < entries_.size(); ++e) keys += e == 0 || entries_[e].key != entries_[e - 1].key ? 1 : 0;
  size_t slots = 16;
  while (slots < 2 * keys) slots *= 2;
  runs_.assign(slots, Run{0, 0, 0});
  run_mask_ = slots - 1;
  for (size_t begin = 0; begin < entries_.size();) {
    size_t end = begin + 1;
    while (end < entries_.size() && entries_[end].key == entries_[begin].key) ++end;
    uint64_t slot = MixKey(entries_[begin].key) & run_mask_;
    while (runs_[slot].end != 0) slot = (slot + 1) & run_mask_;
    runs_[slot] = {entries_[begin].key, static_cast<uint32_t>(begin), static_cast<uint32_t>(end)};
    begin = end;
  }
}

const PpfModel::Run* PpfModel::FindRun(uint64_t key) const {
  for (uint64_t slot = MixKey(key) & run_mask_;; slot = (slot + 1) & run_mask_) {
    const Run& run = runs_[slot];
    if (run.end == 0) return nullptr;
    if (run.key == key) return &run;
  }
}

std::optional<uint64_t> PpfModel::Key(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1, const Eigen::Vector3f& p2,
                                      const Eigen::Vector3f& n2) const {
  const Eigen::Vector3f d = p2 - p1;
  const float distance = d.norm();
  if (distance <= 0 || distance > max_distance_) return std::nullopt;
  const auto step = static_cast<float>(settings_.angle_step_rad);
  // The normals are unit: acos of the clamped dot is the angle, at a fraction of atan2's cost.
  const auto angle = [](float cosine) { return std::acos(std::clamp(cosine, -1.0f, 1.0f)); };
  const float normals_angle = angle(n1.dot(n2));
  if (normals_angle < step) return std::nullopt;
  const Eigen::Vector3f direction = d / distance;
  const auto bin = [&](float a) { return static_cast<uint64_t>(a / step); };
  const auto distance_bin = static_cast<uint64_t>(distance / static_cast<float>(settings_.distance_step));
  return (distance_bin << 48) | (bin(angle(n1.dot(direction))) << 32) | (bin(angle(n2.dot(direction))) << 16) |
         bin(normals_angle);
}

std::optional<uint64_t> PpfModel::RimKey(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1,
                                         const Eigen::Vector3f& p2, const Eigen::Vector3f& n2,
                                         const Eigen::Vector3f& rim2) const {
  const Eigen::Vector3f d = p2 - p1;
  const float distance = d.norm();
  if (distance <= 0 || distance > max_distance_) return std::nullopt;
  const auto step = static_cast<float>(settings_.angle_step_rad);
  const auto bin = [&](float cosine) { return static_cast<uint64_t>(std::acos(std::clamp(cosine, -1.0f, 1.0f)) / step); };
  const Eigen::Vector3f direction = d / distance;
  const auto distance_bin = static_cast<uint64_t>(distance / static_cast<float>(settings_.distance_step));
  return kRimKeyFlag | (distance_bin << 48) | (bin(n1.dot(direction)) << 36) | (bin(rim2.dot(direction)) << 24) |
         (bin(n1.dot(rim2)) << 12) | bin(n1.dot(n2));
}

std::vector<PoseCandidate> PpfModel::Vote(std::span<const Eigen::Vector3f> points,
                                          std::span<const Eigen::Vector3f> normals,
                                          std::span<const Eigen::Vector3f> rims,
                                          const std::atomic<bool>* cancel) const {
  const size_t alpha_bins = alpha_bins_;
  const size_t stride = std::max(1u, settings_.scene_reference_stride);
  const size_t references = (points.size() + stride - 1) / stride;
  const float max_sq = max_distance_ * max_distance_;
  std::vector<ReferenceVote> best(references);

  tbb::parallel_for(tbb::blocked_range<size_t>(0, references, 8), [&](const tbb::blocked_range<size_t>& range) {
    std::vector<uint32_t> accumulator(points_.size() * alpha_bins);
    for (size_t r = range.begin(); r != range.end(); ++r) {
      if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return;
      const size_t s = r * stride;
      const Eigen::Isometry3f frame = LocalFrame(points[s], normals[s]);
      std::fill(accumulator.begin(), accumulator.end(), 0u);
      for (size_t j = 0; j < points.size(); ++j) {
        if (j == s || (points[j] - points[s]).squaredNorm() > max_sq) continue;
        const uint16_t alpha_scene = AlphaOf(frame * points[j]);
        const auto vote = [&](std::optional<uint64_t> key) {
          if (!key) return;
          const Run* run = FindRun(*key);
          if (run == nullptr) return;
          for (uint32_t e = run->begin; e < run->end; ++e) {
            const Entry& entry = entries_[e];
            const auto turn = static_cast<uint16_t>(entry.alpha - alpha_scene);
            ++accumulator[entry.slot + ((static_cast<uint32_t>(turn) * alpha_bins_) >> 16)];
          }
        };
        vote(Key(points[s], normals[s], points[j], normals[j]));
        if (!rims.empty() && !rims[j].isZero()) vote(RimKey(points[s], normals[s], points[j], normals[j], rims[j]));
      }
      const auto peak = std::max_element(accumulator.begin(), accumulator.end());
      if (*peak == 0) continue;
      const auto index = static_cast<size_t>(peak - accumulator.begin());
      const size_t model_reference = index / alpha_bins;
      const double alpha = (static_cast<double>(index % alpha_bins) + 0.5) * kTwoPi / static_cast<double>(alpha_bins);
      // Scene point = frame^-1 * Rx(-alpha) * model frame * model point.
      const Eigen::Isometry3d model_frame = LocalFrame(points_[model_reference], normals_[model_reference]).cast<double>();
      Pose3 pose = frame.cast<double>().inverse() * Eigen::AngleAxisd(-alpha, Eigen::Vector3d::UnitX()) * model_frame;
      best[r] = {pose, *peak};
    }
  });
  if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return {};

  // Clusters seeded by the strongest poses; a pose joins the first cluster whose seed it lies close
  // to, and each cluster's pose is the vote-weighted mean of its members (Vidal et al. 2018).
  std::vector<size_t> order(references);
  for (size_t r = 0; r < references; ++r) order[r] = r;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return best[a].votes > best[b].votes; });
  struct Cluster {
    Pose3 seed;
    uint32_t votes;
    Eigen::Vector4d rotation_sum;  // quaternion coefficients, on the seed's side
    Eigen::Vector3d translation_sum;
  };
  std::vector<Cluster> clusters;
  for (const size_t r : order) {
    if (best[r].votes == 0) break;
    const Pose3& pose = best[r].pose;
    const double weight = best[r].votes;
    Eigen::Vector4d q = Eigen::Quaterniond(pose.linear()).coeffs();
    auto joined = std::find_if(clusters.begin(), clusters.end(), [&](const Cluster& c) {
      return (c.seed.translation() - pose.translation()).norm() <= settings_.cluster_distance &&
             RotationAngle(c.seed, pose) <= settings_.cluster_angle_rad;
    });
    if (joined == clusters.end()) {
      clusters.push_back({pose, best[r].votes, weight * q, weight * pose.translation()});
      continue;
    }
    if (q.dot(joined->rotation_sum) < 0) q = -q;
    joined->votes += best[r].votes;
    joined->rotation_sum += weight * q;
    joined->translation_sum += weight * pose.translation();
  }
  std::vector<PoseCandidate> candidates;
  candidates.reserve(clusters.size());
  for (const Cluster& c : clusters) {
    Pose3 mean = Pose3::Identity();
    mean.linear() = Eigen::Quaterniond(c.rotation_sum.normalized()).toRotationMatrix();
    mean.translation() = c.translation_sum / static_cast<double>(c.votes);
    candidates.push_back({mean, c.votes});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const PoseCandidate& a, const PoseCandidate& b) { return a.votes > b.votes; });
  return candidates;
}

}  // namespace vscan::localization
