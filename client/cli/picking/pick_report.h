#pragma once
// The text `vscan grasps` and `vscan picks` print: one line per grasp or per part, then a summary.

#include <string>
#include <vector>

#include "vscan/v1/picking.pb.h"

namespace vscan::cli {

// "COVERED", "UNREACHABLE", ...; "PICKABLE" for the zero value.
std::string PickFailureWord(v1::PickFailure failure);

// A header, then per grasp: index, quality, tool position (m), approach, opening (mm).
std::vector<std::string> GraspLines(const v1::GenerateGraspsResponse& response);

// Per part: label, object id, pickable (grasp, tool position, approach) or the failure, its detail
// and what covers it; then "N of M parts pickable".
std::vector<std::string> PickLines(const v1::CheckPicksResponse& response);

}  // namespace vscan::cli
