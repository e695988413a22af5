#include "service/model/model_frame.h"

#include <numbers>

namespace vscan::service {

double DegreesToRadians(double degrees) { return degrees * std::numbers::pi / 180.0; }

Pose3 ModelFromWorld(const std::optional<store::TableRecord>& table, std::optional<double> table_angle_deg) {
  if (!table || !table->enabled || !table_angle_deg) return Pose3::Identity();
  return RotationAboutLine(table->centre, table->axis, -DegreesToRadians(*table_angle_deg));
}

Pose3 WorldFromModel(const std::optional<store::TableRecord>& table, double table_angle_deg) {
  if (!table || !table->enabled) return Pose3::Identity();
  return RotationAboutLine(table->centre, table->axis, DegreesToRadians(table_angle_deg));
}

}  // namespace vscan::service
