#pragma once
// The evaluation stage of a model job: the union and the mesh against the ground truth cut to the
// crop (what a scan of the object on its table can see), which true samples the union covers, the
// uncovered samples as a PLY and the coverage picture.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "service/model/model_crop.h"
#include "service/model/model_ground_truth.h"
#include "service/model/model_report.h"
#include "vscan/common/mesh.h"

namespace vscan::service {

struct ModelVerdict {
  ModelEvaluationReport report;  // artifact names left empty
  std::vector<Eigen::Vector3f> samples;
  std::vector<uint8_t> covered;  // one per sample
  std::string uncovered_ply;
  std::string coverage_png;
};

// tau > 0; mesh may be null. up is the table's axis.
StatusOr<ModelVerdict> EvaluateModel(const ModelGroundTruth& truth, const ModelCrop& crop, double tau,
                                     std::span<const Eigen::Vector3f> union_points, const TriangleMesh* mesh,
                                     const Eigen::Vector3d& up);

// Which samples are covered, given the uncovered ones in sample order (a subsequence of samples).
std::vector<uint8_t> CoveredMask(std::span<const Eigen::Vector3f> samples,
                                 std::span<const Eigen::Vector3f> uncovered);

}  // namespace vscan::service
