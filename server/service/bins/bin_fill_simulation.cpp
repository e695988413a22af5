#include "service/bins/bin_fill_simulation.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "physics/bullet_fill_world.h"
#include "physics/fill_loop.h"

namespace vscan::service {

physics::FillResult SimulateBinFill(const BinFillPlan& plan, const std::atomic<bool>* cancel,
                                    ProgressFillWorld::Observer observer, BinReplay* replay) {
  const physics::BinSpec& bin = plan.request.bin;
  const physics::FillOptions& options = plan.request.options;
  const auto start = std::chrono::steady_clock::now();
  // The plan holds hulls only; parts that collide as their convex decomposition get it here.
  const bool decomposed = std::any_of(plan.parts.begin(), plan.parts.end(), [](const physics::PartType& part) {
    return part.collision == physics::PartCollision::kConvexDecomposition;
  });
  const std::vector<physics::PartGeometry> geometry =
      decomposed ? physics::MakePartGeometries(plan.parts, options.hull_tolerance_m) : plan.geometry;
  std::unique_ptr<physics::FillWorld> bullet = physics::MakeBulletFillWorld(bin, geometry, options);
  std::optional<BinReplayRecorder> recorder;
  if (replay != nullptr) {
    std::vector<Eigen::Vector3d> centres;
    for (const physics::PartGeometry& part : geometry) centres.push_back(part.centre);
    recorder.emplace(options.time_step_s, std::move(centres), plan.parts_total());
    bullet = std::make_unique<RecordingFillWorld>(std::move(bullet), *recorder);
  }
  ProgressFillWorld world(std::move(bullet), options.time_step_s, options.sleep_linear_m_per_s,
                          options.sleep_angular_rad_per_s, std::move(observer));
  const double setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  physics::FillResult result = physics::RunFill(bin, plan.parts, geometry, options, world, cancel);
  result.setup_wall_s = setup_s;
  if (recorder) {
    recorder->Finish(result);
    *replay = recorder->Replay();
  }
  return result;
}

}  // namespace vscan::service
