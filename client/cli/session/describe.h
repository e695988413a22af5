#pragma once
// Human-readable one-liners for wire messages.

#include <string>

#include "vscan/v1/cloud.pb.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::cli {

std::string Describe(const v1::Vector3& v);
std::string Describe(const v1::Pose& pose);
std::string Describe(const v1::RotaryTable& table);
// A preset's name, or its four values.
std::string Describe(const v1::Material& material);
std::string Describe(const v1::SceneObject& object);
std::string Describe(const v1::Mesh& mesh);
std::string Describe(const v1::Cloud& cloud);
std::string UnitName(v1::LengthUnit unit);

}  // namespace vscan::cli
