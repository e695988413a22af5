#pragma once
// The model frame: the world with the rotary table at 0 degrees. A scan taken at table angle a is
// turned back by -a about the table's axis through its centre; a cloud without a table (or without
// an angle) is in the model frame as it is.

#include <optional>

#include "store/catalogue.h"
#include "vscan/common/pose.h"

namespace vscan::service {

// model_from_world of a scan taken with table (when its scene has one) at table_angle_deg.
Pose3 ModelFromWorld(const std::optional<store::TableRecord>& table, std::optional<double> table_angle_deg);

// world_from_model: where a model-frame pose stands in the world with the table at table_angle_deg.
Pose3 WorldFromModel(const std::optional<store::TableRecord>& table, double table_angle_deg);

double DegreesToRadians(double degrees);

}  // namespace vscan::service
