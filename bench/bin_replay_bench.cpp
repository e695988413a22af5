// What recording bin_replay.bin costs a bin fill: the fill of docs/BENCHMARKS.md's bin section (a
// 30 x 20 x 15 cm bin, 25 angle blocks and 25 pins) run by the job's SimulateBinFill without and
// with the replay, seed by seed, in alternating order, timed in thread CPU seconds. Also reports
// the replay's frames and bytes, the encoding's time, and whether both runs left the same poses;
// then the recorder's own work apart from the physics: frames sampled from a Bullet world of 50 parts.
// Usage: bin_replay_bench [seeds=3] [repeats=2]

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <vector>

#include "fixture_parts.h"
#include "physics/bullet_fill_world.h"
#include "physics/part_geometry.h"
#include "service/bins/bin_fill_simulation.h"
#include "service/bins/bin_replay.h"

namespace vscan::bench {
namespace {

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

service::BinFillPlan Plan(uint64_t seed) {
  service::BinFillPlan plan;
  plan.request.bin.inner_size = Eigen::Vector3d(0.30, 0.20, 0.15);
  plan.request.options.seed = seed;
  plan.parts = {physics::test::AngleBlock(25), physics::test::RoundPin(25)};
  plan.geometry = physics::MakePartGeometries(plan.parts, plan.request.options.hull_tolerance_m);
  return plan;
}

bool SamePoses(const physics::FillResult& a, const physics::FillResult& b) {
  if (a.parts.size() != b.parts.size() || a.steps != b.steps) return false;
  for (size_t i = 0; i < a.parts.size(); ++i) {
    if (a.parts[i].world_from_part.matrix() != b.parts[i].world_from_part.matrix()) return false;
  }
  return true;
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  using namespace vscan;
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 3;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 2;
  std::printf("| seed | end | simulated s | steps | CPU s plain | CPU s recorded | recorded / plain | frames | "
              "bytes | encode ms | same poses |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  double plain_total = 0, recorded_total = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const service::BinFillPlan plan = bench::Plan(static_cast<uint64_t>(seed));
    double plain_s = 0, recorded_s = 0, encode_s = 0;
    physics::FillResult plain, recorded;
    service::BinReplay replay;
    size_t bytes = 0;
    for (int r = 0; r < repeats; ++r) {
      // Alternate which goes first, so that a change of load hits both alike.
      for (int k = 0; k < 2; ++k) {
        const bool record = (k + r) % 2 == 1;
        const double start = bench::ThreadCpuSeconds();
        if (record) {
          recorded = service::SimulateBinFill(plan, nullptr, nullptr, &replay);
          const double encoded = bench::ThreadCpuSeconds();
          recorded_s += encoded - start;
          bytes = service::EncodeBinReplay(replay).size();
          encode_s += bench::ThreadCpuSeconds() - encoded;
        } else {
          plain = service::SimulateBinFill(plan, nullptr, nullptr);
          plain_s += bench::ThreadCpuSeconds() - start;
        }
      }
    }
    plain_total += plain_s;
    recorded_total += recorded_s;
    std::printf("| %d | %s | %.2f | %llu | %.3f | %.3f | %.4f | %zu | %zu | %.2f | %s |\n", seed,
                physics::FillEndName(plain.end), plain.simulated_s, static_cast<unsigned long long>(plain.steps),
                plain_s / repeats, recorded_s / repeats, recorded_s / plain_s, replay.frames(), bytes,
                1e3 * encode_s / repeats, bench::SamePoses(plain, recorded) ? "yes" : "NO");
  }
  std::printf("\nall seeds: recorded / plain CPU = %.4f\n", recorded_total / plain_total);

  // One frame's cost alone: 50 parts in a Bullet world, a sample every step (no physics stepped).
  const service::BinFillPlan plan = bench::Plan(1);
  const physics::FillOptions& options = plan.request.options;
  std::unique_ptr<physics::FillWorld> world = physics::MakeBulletFillWorld(plan.request.bin, plan.geometry, options);
  std::vector<Eigen::Vector3d> centres;
  for (const physics::PartGeometry& part : plan.geometry) centres.push_back(part.centre);
  constexpr int kFrames = 2000;
  service::BinReplayRecorder recorder(options.time_step_s, centres, 50, options.time_step_s, size_t{1} << 30);
  for (size_t i = 0; i < 50; ++i) {
    Pose3 pose = Pose3::Identity();
    pose.translation() = Eigen::Vector3d(0.005 * static_cast<double>(i), 0, 0.05 * static_cast<double>(i));
    recorder.Added(world->AddPart(i % 2, pose), i % 2);
  }
  const double start = bench::ThreadCpuSeconds();
  for (int f = 0; f < kFrames; ++f) recorder.Sample(static_cast<uint64_t>(f), *world);
  const double per_frame = (bench::ThreadCpuSeconds() - start) / kFrames;
  std::printf("one frame of 50 parts: %.2f us CPU (%d frames)\n", 1e6 * per_frame, kFrames);
  return 0;
}
