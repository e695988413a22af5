#pragma once
// bin_replay.bin: every part's pose through a bin fill, sampled at a fixed simulated-time interval
// for the web view to play back. The recorder wraps the fill's physics world and only reads it, so
// a fill recorded gives the same bits as one not recorded.
//
// Layout (little-endian, docs/BINS.md "The replay"):
//   24-byte header: "VSBR", uint32 version (1), uint32 part count P, uint32 frame count F,
//                   float32 sample interval s (after thinning), uint32 0
//   P x (uint32 type, uint32 instance): the parts in drop order (bin.json's "type" and "instance")
//   F frames: float32 simulated s, then P x float32 (x y z qx qy qz qw): world_from_part (the part's
//             mesh frame, as bin.json's world_from_part, scale not included); all seven NaN while
//             the part is not in the world (not yet dropped, or out of the bin and removed).
// The last frame is the final pile, at the poses bin.json holds (after the overlap separation).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <memory>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "physics/bin_fill.h"
#include "physics/fill_world.h"
#include "vscan/common/status.h"

namespace vscan::service {

inline constexpr char kBinReplayMagic[4] = {'V', 'S', 'B', 'R'};
inline constexpr uint32_t kBinReplayVersion = 1;
inline constexpr size_t kBinReplayHeaderBytes = 24;
inline constexpr size_t kBinReplayFloatsPerPart = 7;
// The record stays within this however long the fill: longer fills are sampled more thinly.
inline constexpr size_t kMaxBinReplayBytes = size_t{4} << 20;
inline constexpr double kBinReplaySampleInterval = 1.0 / 30.0;

struct BinReplayPart {
  uint32_t type = 0;
  uint32_t instance = 0;
};

struct BinReplay {
  float sample_interval_s = 0;
  std::vector<BinReplayPart> parts;
  std::vector<float> times;  // one per frame
  // frames x parts x 7 floats, NaN where the part is absent.
  std::vector<float> poses;
  size_t frames() const { return times.size(); }
};

size_t BinReplayBytes(size_t parts, size_t frames);
std::string EncodeBinReplay(const BinReplay& replay);
// DATA_LOSS naming what is wrong unless bytes are one whole replay of this layout.
StatusOr<BinReplay> DecodeBinReplay(std::string_view bytes);

// Collects the frames of one fill. Samples every interval_steps steps (and at step 0); when the
// next frame would take the record past max_bytes for max_parts parts, every other frame is
// dropped and the interval doubled, so the record stays within max_bytes and evenly spaced.
class BinReplayRecorder {
 public:
  // centres[type]: the part's centre of mass in its mesh frame (the body frame's origin).
  BinReplayRecorder(double time_step_s, std::vector<Eigen::Vector3d> centres, size_t max_parts,
                    double sample_interval_s = kBinReplaySampleInterval, size_t max_bytes = kMaxBinReplayBytes);

  void Added(size_t body, size_t type);
  void Removed(size_t body);
  bool Due(uint64_t step) const { return step % interval_steps_ == 0; }
  // The poses of the parts in the world after `step` steps.
  void Sample(uint64_t step, const physics::FillWorld& world);
  // The final pile as the fill left it: result.parts at their poses, every other part absent.
  void Finish(const physics::FillResult& result);

  BinReplay Replay() const;
  uint64_t interval_steps() const { return interval_steps_; }
  size_t max_frames() const { return max_frames_; }

 private:
  struct Frame {
    uint64_t step = 0;
    float time_s = 0;
    std::vector<float> poses;  // 7 per part added so far (NaN: absent)
  };
  void Thin();
  static void Put(std::vector<float>& poses, size_t part, const Pose3& world_from_part);

  double time_step_s_;
  std::vector<Eigen::Vector3d> centres_;
  uint64_t interval_steps_;
  size_t max_frames_;
  std::vector<BinReplayPart> parts_;
  std::unordered_map<size_t, size_t> live_;  // body -> part index
  std::vector<Frame> frames_;
  bool finished_ = false;
};

// A FillWorld that passes every call on and shows the recorder each part added and removed and the
// world after each step it is due.
class RecordingFillWorld final : public physics::ForwardingFillWorld {
 public:
  RecordingFillWorld(std::unique_ptr<physics::FillWorld> world, BinReplayRecorder& recorder)
      : ForwardingFillWorld(std::move(world)), recorder_(recorder) {}

  size_t AddPart(size_t type, const Pose3& world_from_body) override;
  void RemovePart(size_t body) override;
  void Step() override;

 private:
  BinReplayRecorder& recorder_;
  uint64_t steps_ = 0;
};

}  // namespace vscan::service
