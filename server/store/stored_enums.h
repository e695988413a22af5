#pragma once
// The enums the catalogue stores, and the stable integer code each value is written as. The codes
// are part of the file format: never renumber one (they match what schema version 1 wrote).
// Reading a code no map knows is DATA_LOSS.

#include <cstdint>
#include <string>
#include <string_view>

#include "store/enum_map.h"
#include "vscan/common/status.h"

namespace vscan::store {

// Keep kLast naming the last value: the maps below are checked against it.
enum class JobState { kQueued, kRunning, kSucceeded, kFailed, kCancelled, kInterrupted, kLast = kInterrupted };
enum class LengthUnit { kUnspecified, kMetre, kCentimetre, kMillimetre, kInch, kFoot, kLast = kFoot };
enum class JointKind { kRevolute, kContinuous, kPrismatic, kFixed, kLast = kFixed };
enum class CloudOrigin { kUploaded, kCampaignScan, kLast = kCampaignScan };
enum class CloudFrame { kWorld, kSensor, kLast = kSensor };

inline constexpr EnumMap<JobState, int64_t, 6> kJobStateCodes({{
    {JobState::kQueued, 1},
    {JobState::kRunning, 2},
    {JobState::kSucceeded, 3},
    {JobState::kFailed, 4},
    {JobState::kCancelled, 5},
    {JobState::kInterrupted, 6},
}});
static_assert(kJobStateCodes.CoversFirst(JobState::kQueued, JobState::kLast), "a JobState has no stored code");

inline constexpr EnumMap<LengthUnit, int64_t, 6> kLengthUnitCodes({{
    {LengthUnit::kUnspecified, 0},
    {LengthUnit::kMetre, 1},
    {LengthUnit::kCentimetre, 2},
    {LengthUnit::kMillimetre, 3},
    {LengthUnit::kInch, 4},
    {LengthUnit::kFoot, 5},
}});
static_assert(kLengthUnitCodes.CoversFirst(LengthUnit::kUnspecified, LengthUnit::kLast),
              "a LengthUnit has no stored code");

inline constexpr EnumMap<JointKind, int64_t, 4> kJointKindCodes({{
    {JointKind::kRevolute, 1},
    {JointKind::kContinuous, 2},
    {JointKind::kPrismatic, 3},
    {JointKind::kFixed, 4},
}});
static_assert(kJointKindCodes.CoversFirst(JointKind::kRevolute, JointKind::kLast), "a JointKind has no stored code");

inline constexpr EnumMap<CloudOrigin, int64_t, 2> kCloudOriginCodes({{
    {CloudOrigin::kUploaded, 1},
    {CloudOrigin::kCampaignScan, 2},
}});
static_assert(kCloudOriginCodes.CoversFirst(CloudOrigin::kUploaded, CloudOrigin::kLast),
              "a CloudOrigin has no stored code");

inline constexpr EnumMap<CloudFrame, int64_t, 2> kCloudFrameCodes({{
    {CloudFrame::kWorld, 1},
    {CloudFrame::kSensor, 2},
}});
static_assert(kCloudFrameCodes.CoversFirst(CloudFrame::kWorld, CloudFrame::kLast), "a CloudFrame has no stored code");

// The stored code of a value (every value has one, checked above).
template <typename E, size_t N>
constexpr int64_t StoredCode(const EnumMap<E, int64_t, N>& map, E value) {
  return *map.Forward(value);
}

// The value a stored code names; DATA_LOSS naming where it was read (e.g. "jobs.state of 'job_1'").
template <typename E, size_t N>
StatusOr<E> FromStoredCode(const EnumMap<E, int64_t, N>& map, int64_t code, std::string_view where) {
  if (auto value = map.Backward(code)) return *value;
  return DataLoss("catalogue: " + std::string(where) + " holds unknown code " + std::to_string(code));
}

}  // namespace vscan::store
