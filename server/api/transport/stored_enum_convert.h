#pragma once
// Stored enums <-> wire enums, through maps checked at compile time to cover both sides (the
// wire's UNSPECIFIED aside where the store has no such value).

#include "store/stored_enums.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/robot.pb.h"

namespace vscan::api {

inline constexpr store::EnumMap<store::LengthUnit, v1::LengthUnit, 6> kLengthUnits({{
    {store::LengthUnit::kUnspecified, v1::LENGTH_UNIT_UNSPECIFIED},
    {store::LengthUnit::kMetre, v1::LENGTH_UNIT_METRE},
    {store::LengthUnit::kCentimetre, v1::LENGTH_UNIT_CENTIMETRE},
    {store::LengthUnit::kMillimetre, v1::LENGTH_UNIT_MILLIMETRE},
    {store::LengthUnit::kInch, v1::LENGTH_UNIT_INCH},
    {store::LengthUnit::kFoot, v1::LENGTH_UNIT_FOOT},
}});
static_assert(kLengthUnits.CoversFirst(store::LengthUnit::kUnspecified, store::LengthUnit::kLast));
static_assert(kLengthUnits.CoversSecond(v1::LengthUnit_MIN, v1::LengthUnit_MAX));

inline constexpr store::EnumMap<store::JointKind, v1::JointType, 4> kJointKinds({{
    {store::JointKind::kRevolute, v1::JOINT_TYPE_REVOLUTE},
    {store::JointKind::kContinuous, v1::JOINT_TYPE_CONTINUOUS},
    {store::JointKind::kPrismatic, v1::JOINT_TYPE_PRISMATIC},
    {store::JointKind::kFixed, v1::JOINT_TYPE_FIXED},
}});
static_assert(kJointKinds.CoversFirst(store::JointKind::kRevolute, store::JointKind::kLast));
static_assert(kJointKinds.CoversSecond(v1::JointType(v1::JointType_MIN + 1), v1::JointType_MAX));

}  // namespace vscan::api
