#include "physics/fill_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "physics/mesh_overlap.h"
#include "random/seeded_draws.h"

namespace vscan::physics {
namespace {

using Clock = std::chrono::steady_clock;

struct LivePart {
  size_t body = 0;
  size_t type = 0;
  size_t instance = 0;
  int rest_steps = 0;
  Pose3 anchor = Pose3::Identity();  // where the part was when rest_steps was last zero
};

struct SpawnSlot {
  size_t type = 0;
  size_t instance = 0;
};

// Uniform over rotations (Shoemake, "Uniform random rotations", Graphics Gems III).
Eigen::Quaterniond UniformRotation(random::SplitMix64Stream& draws) {
  const double u1 = draws.Uniform(), u2 = 2 * M_PI * draws.Uniform(), u3 = 2 * M_PI * draws.Uniform();
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  return Eigen::Quaterniond(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3));
}

// Every instance of every type, in a seeded order so that types mix.
std::vector<SpawnSlot> SpawnOrder(const std::vector<PartType>& parts, random::SplitMix64Stream& draws) {
  std::vector<size_t> types;
  for (size_t t = 0; t < parts.size(); ++t) types.insert(types.end(), parts[t].count, t);
  for (size_t i = types.size(); i > 1; --i) {
    const auto j = static_cast<size_t>(draws.Uniform() * static_cast<double>(i));
    std::swap(types[i - 1], types[std::min(j, i - 1)]);
  }
  std::vector<size_t> next_instance(parts.size(), 0);
  std::vector<SpawnSlot> order;
  order.reserve(types.size());
  for (size_t t : types) order.push_back({t, next_instance[t]++});
  return order;
}

class Filler {
 public:
  // start: parts already in the bin (nothing is dropped then); null: the parts' counts are dropped.
  Filler(const BinSpec& bin, const std::vector<PartType>& parts, const std::vector<PartGeometry>& geometry,
         const FillOptions& options, FillWorld& world, const std::vector<PlacedPart>* start)
      : bin_(bin), parts_(parts), geometry_(geometry), options_(options), world_(world), draws_(options.seed),
        bin_from_world_(bin.world_from_bin.inverse()), interior_(InteriorOf(bin)), rim_(interior_.hi.z()),
        max_steps_(static_cast<uint64_t>(std::ceil(options.max_simulated_s / options.time_step_s - 1e-9))) {
    if (start == nullptr) {
      order_ = SpawnOrder(parts, draws_);
      return;
    }
    for (const PlacedPart& part : *start) {
      Pose3 part_from_body = Pose3::Identity();
      part_from_body.translation() = geometry_[part.type].centre;
      const Pose3 world_from_body = part.world_from_part * part_from_body;
      live_.push_back({world_.AddPart(part.type, world_from_body), part.type, part.instance, 0, world_from_body});
    }
  }

  FillResult Run(const std::atomic<bool>* cancel) {
    const auto start = Clock::now();
    FillResult result;
    for (;;) {
      if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
        Finish(result, FillEnd::kCancelled, "cancelled after " + std::to_string(steps_) + " steps");
        break;
      }
      if (!full_ && next_ < order_.size() && DropDue()) DropWave();
      if (!settling_ && (full_ || (next_ == order_.size() && DropDue()))) {
        world_.SetDamping(options_.settle_damping);
        settling_ = true;
      }
      if (steps_ >= max_steps_) {
        if (full_) {
          Finish(result, FillEnd::kFull, full_message_ + "; not at rest by the time bound");
        } else {
          Finish(result, FillEnd::kTimeBound, "not at rest after " + std::to_string(options_.max_simulated_s) + " s");
        }
        break;
      }
      world_.Step();
      ++steps_;
      if (UpdateParts() && (full_ || next_ == order_.size())) {
        Finish(result, full_ ? FillEnd::kFull : FillEnd::kSettled, full_ ? full_message_ : "every part at rest");
        break;
      }
    }
    result.step_wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  }

 private:
  double TopInBin(size_t type, const Pose3& world_from_body) const {
    const Pose3 bin_from_body = bin_from_world_ * world_from_body;
    double top = -std::numeric_limits<double>::infinity();
    for (const auto& p : geometry_[type].hull) top = std::max(top, (bin_from_body * p).z());
    return top;
  }

  bool DropDue() const {
    if (wave_.empty()) return true;
    if (Seconds() - last_drop_s_ >= options_.drop_interval_s) return true;
    for (size_t body : wave_) {
      const auto it = std::find_if(live_.begin(), live_.end(), [&](const LivePart& p) { return p.body == body; });
      if (it != live_.end() && TopInBin(it->type, world_.State(body).world_from_body) >= rim_) return false;
    }
    return true;
  }

  // Bin-frame centres and radii of the parts in the world, for the spawn's clearance test.
  bool Clear(const Eigen::Vector3d& centre, double radius,
             const std::vector<std::pair<Eigen::Vector3d, double>>& others) const {
    for (const auto& [c, r] : others) {
      if ((c - centre).squaredNorm() < (r + radius) * (r + radius)) return false;
    }
    return true;
  }

  void DropWave() {
    std::vector<std::pair<Eigen::Vector3d, double>> occupied;
    for (const LivePart& p : live_) {
      occupied.emplace_back(bin_from_world_ * world_.State(p.body).world_from_body.translation(),
                            geometry_[p.type].radius);
    }
    wave_.clear();
    for (int k = 0; k < options_.parts_per_drop && next_ < order_.size(); ++k) {
      const SpawnSlot slot = order_[next_];
      const double r = geometry_[slot.type].radius;
      const Eigen::Vector3d middle = 0.5 * (interior_.lo + interior_.hi);
      const Eigen::Vector3d opening = interior_.hi - interior_.lo;
      // A mesh's opening is only known by its bounding box: a part wider than that cannot go in.
      if (!bin_.mesh.empty() && 2 * r > opening.head<2>().minCoeff()) {
        full_ = true;
        full_message_ = "the bin's opening (" + std::to_string(opening.x()) + " x " + std::to_string(opening.y()) +
                        " m) is narrower than parts[" + std::to_string(slot.type) + "] (" + std::to_string(2 * r) +
                        " m across)";
        break;
      }
      const double half_x = std::max(0.0, 0.5 * opening.x() - r);
      const double half_y = std::max(0.0, 0.5 * opening.y() - r);
      const double z = rim_ + options_.drop_clearance_m + r;
      bool placed = false;
      for (int attempt = 0; attempt < options_.spawn_attempts && !placed; ++attempt) {
        const Eigen::Vector3d centre(middle.x() + (2 * draws_.Uniform() - 1) * half_x,
                                     middle.y() + (2 * draws_.Uniform() - 1) * half_y, z);
        const Eigen::Quaterniond rotation = UniformRotation(draws_);
        if (!Clear(centre, r, occupied)) continue;
        Pose3 bin_from_body = Pose3::Identity();
        bin_from_body.translation() = centre;
        bin_from_body.linear() = rotation.toRotationMatrix();
        const size_t body = world_.AddPart(slot.type, bin_.world_from_bin * bin_from_body);
        live_.push_back({body, slot.type, slot.instance, 0, bin_.world_from_bin * bin_from_body});
        wave_.push_back(body);
        occupied.emplace_back(centre, r);
        placed = true;
      }
      if (!placed) {
        if (k == 0) {
          full_ = true;
          full_message_ = "no room to drop parts[" + std::to_string(slot.type) + "] instance " +
                          std::to_string(slot.instance) + " clear of the others";
        }
        break;
      }
      ++next_;
    }
    last_drop_s_ = Seconds();
  }

  bool FellOut(const LivePart& part, const Eigen::Vector3d& centre) const {
    const double r = geometry_[part.type].radius;
    const double reach = interior_.wall + r;
    const bool beside = centre.x() < interior_.lo.x() - reach || centre.x() > interior_.hi.x() + reach ||
                        centre.y() < interior_.lo.y() - reach || centre.y() > interior_.hi.y() + reach;
    return (beside && centre.z() < rim_) || centre.z() < interior_.lo.z() - reach;
  }

  // Removes parts that left the bin and counts steps at rest. True when every part is at rest.
  bool UpdateParts() {
    bool all_at_rest = true;
    for (size_t i = 0; i < live_.size();) {
      LivePart& part = live_[i];
      const BodyState state = world_.State(part.body);
      const Eigen::Vector3d centre = bin_from_world_ * state.world_from_body.translation();
      if (FellOut(part, centre)) {
        outside_.push_back(Placed(part, state));
        world_.RemovePart(part.body);
        live_.erase(live_.begin() + static_cast<std::ptrdiff_t>(i));
        continue;
      }
      if (StayedNearAnchor(part, state.world_from_body)) {
        ++part.rest_steps;
      } else {
        part.anchor = state.world_from_body;
        part.rest_steps = 0;
      }
      if (part.rest_steps == options_.settle_steps && !full_ &&
          TopInBin(part.type, state.world_from_body) > rim_ + options_.rim_tolerance_m) {
        full_ = true;
        full_message_ = "parts[" + std::to_string(part.type) + "] instance " + std::to_string(part.instance) +
                        " came to rest above the rim";
      }
      all_at_rest = all_at_rest && part.rest_steps >= options_.settle_steps;
      ++i;
    }
    return all_at_rest;
  }

  bool StayedNearAnchor(const LivePart& part, const Pose3& pose) const {
    const double moved = (pose.translation() - part.anchor.translation()).norm();
    const double turned = Eigen::AngleAxisd(part.anchor.linear().transpose() * pose.linear()).angle();
    return moved <= options_.settle_move_m && turned <= options_.settle_turn_rad;
  }

  PlacedPart Placed(const LivePart& part, const BodyState& state) const {
    Pose3 body_from_part = Pose3::Identity();
    body_from_part.translation() = -geometry_[part.type].centre;
    return {part.type, part.instance, state.world_from_body * body_from_part};
  }

  bool InsideInnerBox(const Eigen::Vector3d& centre) const {
    return centre.x() >= interior_.lo.x() && centre.x() <= interior_.hi.x() && centre.y() >= interior_.lo.y() &&
           centre.y() <= interior_.hi.y() && centre.z() >= interior_.lo.z();
  }

  void Finish(FillResult& result, FillEnd end, std::string message) {
    for (const LivePart& part : live_) {
      const BodyState state = world_.State(part.body);
      const bool inside = InsideInnerBox(bin_from_world_ * state.world_from_body.translation());
      (inside ? result.parts : outside_).push_back(Placed(part, state));
      if (!inside) world_.RemovePart(part.body);
    }
    const ContactDepths depths = world_.DeepestContacts();
    result.outside = std::move(outside_);
    result.spawned = next_;
    result.end = end;
    result.message = std::move(message);
    result.simulated_s = Seconds();
    result.steps = steps_;
    result.max_part_part_penetration_m = depths.part_part;
    result.max_part_bin_penetration_m = depths.part_bin;
    const auto measure_start = Clock::now();
    if (!options_.measure_mesh_overlaps) return;
    result.mesh_overlap = options_.max_mesh_overlap_m > 0
                              ? SeparateMeshOverlaps(bin_, parts_, result.parts, options_.max_mesh_overlap_m,
                                                     options_.separation_rounds)
                              : MeasureMeshOverlaps(bin_, parts_, result.parts);
    result.measure_wall_s = std::chrono::duration<double>(Clock::now() - measure_start).count();
  }

  double Seconds() const { return static_cast<double>(steps_) * options_.time_step_s; }

  const BinSpec& bin_;
  const std::vector<PartType>& parts_;
  const std::vector<PartGeometry>& geometry_;
  const FillOptions& options_;
  FillWorld& world_;
  random::SplitMix64Stream draws_;
  const Pose3 bin_from_world_;
  const BinInterior interior_;
  const double rim_;
  const uint64_t max_steps_;
  std::vector<SpawnSlot> order_;
  size_t next_ = 0;
  std::vector<LivePart> live_;
  std::vector<size_t> wave_;
  std::vector<PlacedPart> outside_;
  double last_drop_s_ = 0.0;
  uint64_t steps_ = 0;
  bool full_ = false;
  bool settling_ = false;
  std::string full_message_;
};

}  // namespace

FillResult RunFill(const BinSpec& bin, const std::vector<PartType>& parts, const std::vector<PartGeometry>& geometry,
                   const FillOptions& options, FillWorld& world, const std::atomic<bool>* cancel) {
  return Filler(bin, parts, geometry, options, world, nullptr).Run(cancel);
}

FillResult RunSettle(const BinSpec& bin, const std::vector<PartType>& parts, const std::vector<PartGeometry>& geometry,
                     const std::vector<PlacedPart>& placed, const FillOptions& options, FillWorld& world,
                     const std::atomic<bool>* cancel) {
  FillResult result = Filler(bin, parts, geometry, options, world, &placed).Run(cancel);
  result.spawned = 0;
  return result;
}

}  // namespace vscan::physics
