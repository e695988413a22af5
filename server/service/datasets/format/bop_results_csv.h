#pragma once
// A BOP results file (bop_toolkit's inout.load_bop_results, "bop19"): one estimate a line,
// scene_id,im_id,obj_id,score,R,t,time with R nine numbers row-major and t three, in millimetres,
// separated by spaces; camera_from_model. An optional header line comes first.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::service::dataset {

struct BopResultRow {
  size_t line = 0;  // 1-based line of the file
  uint32_t scene_id = 0;
  uint32_t im_id = 0;
  uint32_t obj_id = 0;
  double score = 0;
  Eigen::Matrix3d camera_R_model = Eigen::Matrix3d::Identity();
  Eigen::Vector3d camera_t_model_mm = Eigen::Vector3d::Zero();
  double time = -1;
};

// Largest |t| component accepted, millimetres (10 km: far beyond any scene, far from overflow).
inline constexpr double kMaxResultTranslationMm = 1e7;
// Largest deviation of R^T R from the identity accepted (rounded output of a true rotation passes).
inline constexpr double kMaxResultRotationDeviation = 1e-3;

// INVALID_ARGUMENT naming field, the line and the column for a row that is not seven fields, an id
// that is not a whole number in [0, 2^32), a score or time that is not a finite number, an R that is
// not nine finite numbers forming a rotation, or a t that is not three finite numbers within
// kMaxResultTranslationMm. Blank lines are skipped; "\r\n" ends a line as "\n" does.
StatusOr<std::vector<BopResultRow>> ParseBopResultsCsv(std::string_view text, std::string_view field);

}  // namespace vscan::service::dataset
