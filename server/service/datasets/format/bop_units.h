#pragma once
// BOP writes lengths in millimetres; vscan keeps metres.

namespace vscan::service::dataset {

inline constexpr double kMillimetresPerMetre = 1000.0;

}  // namespace vscan::service::dataset
