#pragma once
// The pieces of JSON the web view's answers are written from (they are small and fixed, so no
// document model): numbers that cannot be JSON become null, matrices are 4 rows of 4.

#include <string>
#include <string_view>

#include <Eigen/Core>

namespace vscan::web {

// NaN and infinities as null, which JSON has in their place.
void AppendJsonNumber(std::string& out, double value);
void AppendJsonString(std::string& out, std::string_view text);
void AppendJsonVector(std::string& out, const Eigen::Vector3d& v);
// [[r0c0, r0c1, r0c2, r0c3], [...], [...], [...]]
void AppendJsonRows(std::string& out, const Eigen::Matrix4d& m);

}  // namespace vscan::web
