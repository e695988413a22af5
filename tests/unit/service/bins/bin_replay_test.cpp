// bin_replay.bin: the bytes of the layout and their reading back, the bound on its size however
// long the fill, and a recorded fill giving the same bits as one not recorded.

#include "service/bins/bin_replay.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include <Eigen/Geometry>

#include "fixture_parts.h"
#include "physics/part_geometry.h"
#include "service/bins/bin_fill_simulation.h"

namespace vscan::service {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

template <typename T>
T At(const std::string& bytes, size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

bool SameFloats(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) != std::isnan(b[i]) || (!std::isnan(a[i]) && a[i] != b[i])) return false;
  }
  return true;
}

BinReplay TwoPartsThreeFrames() {
  BinReplay replay;
  replay.sample_interval_s = 1.0f / 30;
  replay.parts = {{0, 0}, {1, 0}};
  replay.times = {0.0f, 1.0f / 30, 0.5f};
  replay.poses = {
      0.1f, 0.2f, 0.3f, 0, 0, 0, 1,  kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN,  // the second not dropped yet
      0.1f, 0.2f, 0.2f, 0, 0, 0, 1,  -0.1f, 0, 0.4f, 0.5f, 0.5f, 0.5f, 0.5f,
      0.1f, 0.2f, 0.05f, 0, 0, 1, 0, -0.1f, 0, 0.02f, 0.5f, 0.5f, 0.5f, 0.5f,
  };
  return replay;
}

TEST(BinReplay, TheBytesAreTheDocumentedLayoutAndReadBack) {
  const BinReplay replay = TwoPartsThreeFrames();
  const std::string bytes = EncodeBinReplay(replay);
  ASSERT_EQ(bytes.size(), 24u + 2 * 8 + 3 * (4 + 2 * 28));
  EXPECT_EQ(bytes.size(), BinReplayBytes(2, 3));
  EXPECT_EQ(bytes.substr(0, 4), "VSBR");
  EXPECT_EQ(At<uint32_t>(bytes, 4), 1u);
  EXPECT_EQ(At<uint32_t>(bytes, 8), 2u);   // parts
  EXPECT_EQ(At<uint32_t>(bytes, 12), 3u);  // frames
  EXPECT_FLOAT_EQ(At<float>(bytes, 16), 1.0f / 30);
  EXPECT_EQ(At<uint32_t>(bytes, 20), 0u);
  EXPECT_EQ(At<uint32_t>(bytes, 24 + 8), 1u);  // the second part's type
  // The third frame: its time, then the second part's z and qw.
  const size_t frame = 24 + 16 + 2 * (4 + 56);
  EXPECT_FLOAT_EQ(At<float>(bytes, frame), 0.5f);
  EXPECT_FLOAT_EQ(At<float>(bytes, frame + 4 + 28 + 8), 0.02f);
  EXPECT_FLOAT_EQ(At<float>(bytes, frame + 4 + 28 + 24), 0.5f);
  EXPECT_TRUE(std::isnan(At<float>(bytes, 24 + 16 + 4 + 28)));  // absent in the first frame

  auto decoded = DecodeBinReplay(bytes);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_EQ(decoded->sample_interval_s, replay.sample_interval_s);
  ASSERT_EQ(decoded->parts.size(), 2u);
  EXPECT_EQ(decoded->parts[1].type, 1u);
  EXPECT_EQ(decoded->times, replay.times);
  EXPECT_TRUE(SameFloats(decoded->poses, replay.poses));
}

TEST(BinReplay, BytesOfAnotherShapeAreRefused) {
  const std::string bytes = EncodeBinReplay(TwoPartsThreeFrames());
  std::string wrong_magic = bytes;
  wrong_magic[3] = 'X';
  std::string newer = bytes;
  newer[4] = 2;
  std::string more_frames = bytes;
  more_frames[12] = 4;
  for (const std::string& bad : {bytes.substr(0, bytes.size() - 1), bytes + '\0', bytes.substr(0, 10), wrong_magic,
                                 newer, more_frames, std::string()}) {
    const auto decoded = DecodeBinReplay(bad);
    ASSERT_FALSE(decoded.ok()) << bad.size();
    EXPECT_EQ(decoded.status().code(), StatusCode::kDataLoss);
    EXPECT_NE(decoded.status().message().find("bin_replay.bin"), std::string::npos);
  }
  // No parts and no frames is a whole replay.
  EXPECT_TRUE(DecodeBinReplay(EncodeBinReplay(BinReplay{})).ok());
}

// A world whose parts sink 1 mm a step: what the recorder reads of it.
class SinkingWorld final : public physics::FillWorld {
 public:
  size_t AddPart(size_t, const Pose3& world_from_body) override {
    poses.push_back(world_from_body);
    return poses.size() - 1;
  }
  void RemovePart(size_t) override {}
  void Step() override {
    for (Pose3& pose : poses) pose.translation().z() -= 0.001;
  }
  void SetDamping(double) override {}
  physics::BodyState State(size_t body) const override { return {poses[body], 0, 0}; }
  physics::ContactDepths DeepestContacts() override { return {}; }
  std::vector<Pose3> poses;
};

Pose3 At(double x, double y, double z) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

TEST(BinReplay, AShortFillIsSampledEveryThirtiethOfASecond) {
  const double dt = 1.0 / 240;
  const std::vector<Eigen::Vector3d> centres = {Eigen::Vector3d(0, 0, 0.01)};
  BinReplayRecorder recorder(dt, centres, 2);
  EXPECT_EQ(recorder.interval_steps(), 8u);
  RecordingFillWorld world(std::make_unique<SinkingWorld>(), recorder);
  world.AddPart(0, At(0, 0, 1));
  for (int step = 0; step < 240; ++step) {
    if (step == 120) world.AddPart(0, At(0.1, 0, 1));
    world.Step();
  }
  physics::FillResult result;
  result.steps = 240;
  result.simulated_s = 1.0;
  result.parts.push_back({0, 1, At(0.1, 0, 0.5)});  // the second part, moved after the physics
  recorder.Finish(result);
  const BinReplay replay = recorder.Replay();
  // Steps 0, 8, ..., 232, then the final pile in place of the sample at step 240.
  ASSERT_EQ(replay.frames(), 31u);
  EXPECT_NEAR(replay.sample_interval_s, 1.0 / 30, 1e-7);
  ASSERT_EQ(replay.parts.size(), 2u);
  EXPECT_EQ(replay.parts[1].instance, 1u);
  for (size_t f = 0; f + 1 < replay.frames(); ++f) EXPECT_NEAR(replay.times[f], f / 30.0, 1e-6) << f;
  EXPECT_FLOAT_EQ(replay.times.back(), 1.0f);
  // The mesh frame: the body's pose less the centre of mass; the part not dropped yet is NaN.
  EXPECT_NEAR(replay.poses[2], 1 - 0.01, 1e-6);
  EXPECT_TRUE(std::isnan(replay.poses[7]));
  const size_t frame16 = 16 * 14;  // step 128: both parts in
  EXPECT_NEAR(replay.poses[frame16 + 2], 1 - 0.128 - 0.01, 1e-5);
  EXPECT_NEAR(replay.poses[frame16 + 7 + 2], 1 - 0.008 - 0.01, 1e-5);
  EXPECT_FLOAT_EQ(replay.poses[frame16 + 7 + 6], 1.0f);  // qw of the identity
  // The final frame holds result.parts only: the first part is not in the result.
  const size_t last = 30 * 14;
  EXPECT_TRUE(std::isnan(replay.poses[last]));
  EXPECT_FLOAT_EQ(replay.poses[last + 7 + 2], 0.5f);
}

TEST(BinReplay, ALongFillIsThinnedToStayWithinItsBound) {
  const double dt = 1.0 / 240;
  const size_t parts = 50;
  const size_t max_bytes = 100'000;  // room for 70 frames of 50 parts
  BinReplayRecorder recorder(dt, std::vector<Eigen::Vector3d>(1, Eigen::Vector3d::Zero()), parts,
                             1.0 / 30, max_bytes);
  ASSERT_EQ(recorder.max_frames(), (max_bytes - 24 - 8 * parts) / (4 + 28 * parts));
  RecordingFillWorld world(std::make_unique<SinkingWorld>(), recorder);
  for (size_t i = 0; i < parts; ++i) world.AddPart(0, At(0.01 * i, 0, 1));
  const uint64_t steps = 600 * 240;  // the longest fill: 600 simulated seconds
  for (uint64_t step = 0; step < steps; ++step) world.Step();
  physics::FillResult result;
  result.steps = steps;
  result.simulated_s = 600;
  recorder.Finish(result);
  const BinReplay replay = recorder.Replay();
  const std::string bytes = EncodeBinReplay(replay);
  EXPECT_LE(bytes.size(), max_bytes);
  // Thinned by halves: still at least half the frames the bound allows, evenly spaced from 0.
  EXPECT_GE(replay.frames(), recorder.max_frames() / 2);
  EXPECT_LE(replay.frames(), recorder.max_frames());
  const double interval = static_cast<double>(recorder.interval_steps()) * dt;
  EXPECT_EQ(recorder.interval_steps() % 8, 0u);
  EXPECT_GT(interval, 1.0 / 30);
  EXPECT_NEAR(replay.sample_interval_s, interval, 1e-6);
  for (size_t f = 0; f + 1 < replay.frames(); ++f) EXPECT_NEAR(replay.times[f], f * interval, 1e-3) << f;
  EXPECT_FLOAT_EQ(replay.times.back(), 600.0f);
  EXPECT_GT(replay.times[replay.frames() - 2], 600 - 2 * interval);

  // The default bound holds for the largest fill: 500 parts for 600 s.
  BinReplayRecorder largest(dt, std::vector<Eigen::Vector3d>(1, Eigen::Vector3d::Zero()), physics::kMaxFillParts);
  EXPECT_LE(BinReplayBytes(physics::kMaxFillParts, largest.max_frames()), kMaxBinReplayBytes);
  EXPECT_GE(largest.max_frames(), 250u);
}

// The height of a part's centre of mass at a recorded pose (x y z qx qy qz qw of its mesh frame).
double CentreZ(const float* pose, const Eigen::Vector3d& centre) {
  const Eigen::Quaterniond q(pose[6], pose[3], pose[4], pose[5]);
  return pose[2] + (q * centre).z();
}

// A small fill of fixture parts planned without a store, as PlanBinFill would.
BinFillPlan SmallPlan(uint64_t seed) {
  BinFillPlan plan;
  plan.request.bin.inner_size = Eigen::Vector3d(0.20, 0.15, 0.10);
  plan.request.bin.world_from_bin.translation() = Eigen::Vector3d(0.3, -0.1, 0.0);
  plan.request.options.seed = seed;
  plan.request.options.max_simulated_s = 20;
  plan.parts = {physics::test::AngleBlock(4), physics::test::RoundPin(3)};
  plan.geometry = physics::MakePartGeometries(plan.parts, plan.request.options.hull_tolerance_m);
  return plan;
}

TEST(BinReplay, ARecordedFillGivesTheSameBitsAsOneNotRecorded) {
  const BinFillPlan plan = SmallPlan(5);
  const physics::FillResult plain = SimulateBinFill(plan, nullptr, nullptr);
  BinReplay replay;
  const physics::FillResult recorded = SimulateBinFill(plan, nullptr, nullptr, &replay);
  ASSERT_EQ(plain.spawned, 7u);
  ASSERT_EQ(recorded.end, plain.end);
  EXPECT_EQ(recorded.steps, plain.steps);
  ASSERT_EQ(recorded.parts.size(), plain.parts.size());
  ASSERT_GT(plain.parts.size(), 0u);
  for (size_t i = 0; i < plain.parts.size(); ++i) {
    EXPECT_EQ(recorded.parts[i].type, plain.parts[i].type);
    EXPECT_EQ(recorded.parts[i].instance, plain.parts[i].instance);
    EXPECT_EQ(recorded.parts[i].world_from_part.matrix(), plain.parts[i].world_from_part.matrix()) << i;
  }

  // One entry per part dropped, numbered within its type as the result numbers them.
  ASSERT_EQ(replay.parts.size(), plain.spawned);
  std::map<std::pair<uint32_t, uint32_t>, size_t> index;
  for (size_t i = 0; i < replay.parts.size(); ++i) index[{replay.parts[i].type, replay.parts[i].instance}] = i;
  EXPECT_EQ(index.size(), replay.parts.size());
  EXPECT_EQ(replay.frames(), static_cast<size_t>(std::ceil(plain.steps / 8.0)) + 1);
  EXPECT_FLOAT_EQ(replay.times.back(), static_cast<float>(plain.simulated_s));
  const size_t floats = replay.parts.size() * kBinReplayFloatsPerPart;
  const float* first = replay.poses.data();
  const float* last = replay.poses.data() + (replay.frames() - 1) * floats;
  size_t in_first = 0;
  for (const physics::PlacedPart& part : plain.parts) {
    const size_t k = index.at({static_cast<uint32_t>(part.type), static_cast<uint32_t>(part.instance)});
    const float* pose = last + k * kBinReplayFloatsPerPart;
    // The last frame is the settled pile of bin.json, in float32.
    const Eigen::Vector3d t = part.world_from_part.translation();
    for (int a = 0; a < 3; ++a) EXPECT_FLOAT_EQ(pose[a], static_cast<float>(t[a]));
    const Eigen::Quaterniond q(part.world_from_part.linear());
    EXPECT_NEAR(std::abs(q.coeffs().cast<float>().dot(Eigen::Vector4f(pose[3], pose[4], pose[5], pose[6]))), 1, 1e-5);
    // The first frame has the first drop above the rim, higher than where it settles.
    if (!std::isnan(first[k * kBinReplayFloatsPerPart])) {
      ++in_first;
      const Eigen::Vector3d& centre = plan.geometry[part.type].centre;
      EXPECT_GT(CentreZ(first + k * kBinReplayFloatsPerPart, centre), CentreZ(pose, centre) + 0.02) << k;
    }
  }
  EXPECT_GE(in_first, 1u);
  EXPECT_EQ(DecodeBinReplay(EncodeBinReplay(replay))->frames(), replay.frames());
}

}  // namespace
}  // namespace vscan::service
