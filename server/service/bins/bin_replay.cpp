#include "service/bins/bin_replay.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <utility>

#include <Eigen/Geometry>

namespace vscan::service {
namespace {

static_assert(std::endian::native == std::endian::little, "the replay is written as the machine holds it");

constexpr float kAbsent = std::numeric_limits<float>::quiet_NaN();
constexpr size_t kPartEntryBytes = 8;

size_t FrameBytes(size_t parts) { return 4 + parts * kBinReplayFloatsPerPart * 4; }

void Append(std::string& out, const void* data, size_t bytes) { out.append(static_cast<const char*>(data), bytes); }

template <typename T>
T Read(std::string_view bytes, size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

}  // namespace

size_t BinReplayBytes(size_t parts, size_t frames) {
  return kBinReplayHeaderBytes + parts * kPartEntryBytes + frames * FrameBytes(parts);
}

std::string EncodeBinReplay(const BinReplay& replay) {
  const auto parts = static_cast<uint32_t>(replay.parts.size());
  const auto frames = static_cast<uint32_t>(replay.times.size());
  std::string out;
  out.reserve(BinReplayBytes(parts, frames));
  Append(out, kBinReplayMagic, 4);
  Append(out, &kBinReplayVersion, 4);
  Append(out, &parts, 4);
  Append(out, &frames, 4);
  Append(out, &replay.sample_interval_s, 4);
  const uint32_t reserved = 0;
  Append(out, &reserved, 4);
  for (const BinReplayPart& part : replay.parts) {
    Append(out, &part.type, 4);
    Append(out, &part.instance, 4);
  }
  const size_t floats = parts * kBinReplayFloatsPerPart;
  for (size_t f = 0; f < frames; ++f) {
    Append(out, &replay.times[f], 4);
    Append(out, replay.poses.data() + f * floats, floats * 4);
  }
  return out;
}

StatusOr<BinReplay> DecodeBinReplay(std::string_view bytes) {
  if (bytes.size() < kBinReplayHeaderBytes || std::memcmp(bytes.data(), kBinReplayMagic, 4) != 0) {
    return DataLoss("bin_replay.bin: not a replay (no \"VSBR\" header)");
  }
  const auto version = Read<uint32_t>(bytes, 4);
  if (version != kBinReplayVersion) {
    return DataLoss("bin_replay.bin: version " + std::to_string(version) + ", this build reads " +
                    std::to_string(kBinReplayVersion));
  }
  const uint64_t parts = Read<uint32_t>(bytes, 8);
  const uint64_t frames = Read<uint32_t>(bytes, 12);
  // In 64 bits the sizes cannot overflow: at most 2^32 * (4 + 28 * 2^32).
  const uint64_t expected = kBinReplayHeaderBytes + parts * kPartEntryBytes + frames * (4 + parts * 28);
  if (expected != bytes.size()) {
    return DataLoss("bin_replay.bin: " + std::to_string(parts) + " parts and " + std::to_string(frames) +
                    " frames take " + std::to_string(expected) + " bytes, got " + std::to_string(bytes.size()));
  }
  BinReplay replay;
  replay.sample_interval_s = Read<float>(bytes, 16);
  size_t at = kBinReplayHeaderBytes;
  replay.parts.resize(parts);
  for (BinReplayPart& part : replay.parts) {
    part.type = Read<uint32_t>(bytes, at);
    part.instance = Read<uint32_t>(bytes, at + 4);
    at += kPartEntryBytes;
  }
  const size_t floats = parts * kBinReplayFloatsPerPart;
  replay.times.resize(frames);
  replay.poses.resize(frames * floats);
  for (size_t f = 0; f < frames; ++f) {
    replay.times[f] = Read<float>(bytes, at);
    std::memcpy(replay.poses.data() + f * floats, bytes.data() + at + 4, floats * 4);
    at += FrameBytes(parts);
  }
  return replay;
}

BinReplayRecorder::BinReplayRecorder(double time_step_s, std::vector<Eigen::Vector3d> centres, size_t max_parts,
                                     double sample_interval_s, size_t max_bytes)
    : time_step_s_(time_step_s), centres_(std::move(centres)),
      interval_steps_(std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(sample_interval_s / time_step_s)))) {
  const size_t fixed = BinReplayBytes(max_parts, 0);
  max_frames_ = std::max<size_t>(2, max_bytes > fixed ? (max_bytes - fixed) / FrameBytes(max_parts) : 0);
}

void BinReplayRecorder::Added(size_t body, size_t type) {
  const auto instance = static_cast<uint32_t>(
      std::count_if(parts_.begin(), parts_.end(), [&](const BinReplayPart& p) { return p.type == type; }));
  live_[body] = parts_.size();
  parts_.push_back({static_cast<uint32_t>(type), instance});
}

void BinReplayRecorder::Removed(size_t body) { live_.erase(body); }

void BinReplayRecorder::Put(std::vector<float>& poses, size_t part, const Pose3& world_from_part) {
  const Eigen::Vector3d t = world_from_part.translation();
  const Eigen::Quaterniond q(world_from_part.linear());
  float* out = poses.data() + part * kBinReplayFloatsPerPart;
  const double values[kBinReplayFloatsPerPart] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
  for (size_t i = 0; i < kBinReplayFloatsPerPart; ++i) out[i] = static_cast<float>(values[i]);
}

void BinReplayRecorder::Sample(uint64_t step, const physics::FillWorld& world) {
  if (finished_ || !Due(step)) return;
  // Room for this frame and the final one.
  if (frames_.size() + 2 > max_frames_) {
    Thin();
    if (!Due(step)) return;
  }
  Frame frame{step, static_cast<float>(static_cast<double>(step) * time_step_s_),
              std::vector<float>(parts_.size() * kBinReplayFloatsPerPart, kAbsent)};
  for (const auto& [body, part] : live_) {
    Pose3 body_from_part = Pose3::Identity();
    body_from_part.translation() = -centres_[parts_[part].type];
    Put(frame.poses, part, world.State(body).world_from_body * body_from_part);
  }
  frames_.push_back(std::move(frame));
}

void BinReplayRecorder::Thin() {
  const uint64_t interval = interval_steps_ * 2;
  std::erase_if(frames_, [&](const Frame& frame) { return frame.step % interval != 0; });
  interval_steps_ = interval;
}

void BinReplayRecorder::Finish(const physics::FillResult& result) {
  if (finished_) return;
  std::map<std::pair<size_t, size_t>, size_t> index;  // (type, instance) -> part
  for (size_t i = 0; i < parts_.size(); ++i) index[{parts_[i].type, parts_[i].instance}] = i;
  Frame frame{result.steps, static_cast<float>(result.simulated_s),
              std::vector<float>(parts_.size() * kBinReplayFloatsPerPart, kAbsent)};
  for (const physics::PlacedPart& placed : result.parts) {
    const auto it = index.find({placed.type, placed.instance});
    if (it != index.end()) Put(frame.poses, it->second, placed.world_from_part);
  }
  // The last sample may be the final step itself: the final pile (separated) takes its place.
  if (!frames_.empty() && frames_.back().step == result.steps) frames_.pop_back();
  frames_.push_back(std::move(frame));
  finished_ = true;
}

BinReplay BinReplayRecorder::Replay() const {
  BinReplay replay;
  replay.sample_interval_s = static_cast<float>(static_cast<double>(interval_steps_) * time_step_s_);
  replay.parts = parts_;
  const size_t floats = parts_.size() * kBinReplayFloatsPerPart;
  replay.times.reserve(frames_.size());
  replay.poses.assign(frames_.size() * floats, kAbsent);
  for (size_t f = 0; f < frames_.size(); ++f) {
    replay.times.push_back(frames_[f].time_s);
    std::copy(frames_[f].poses.begin(), frames_[f].poses.end(), replay.poses.begin() + f * floats);
  }
  return replay;
}

size_t RecordingFillWorld::AddPart(size_t type, const Pose3& world_from_body) {
  const size_t body = inner().AddPart(type, world_from_body);
  recorder_.Added(body, type);
  return body;
}

void RecordingFillWorld::RemovePart(size_t body) {
  inner().RemovePart(body);
  recorder_.Removed(body);
}

void RecordingFillWorld::Step() {
  // Step 0: the first drop where it starts, above the bin.
  if (steps_ == 0) recorder_.Sample(0, inner());
  inner().Step();
  ++steps_;
  recorder_.Sample(steps_, inner());
}

}  // namespace vscan::service
