#pragma once
// models/models_info.json as BOP has it: per part type, the diameter and the bounding box in
// millimetres, and its symmetries when it has any.

#include <string>
#include <vector>

#include "service/datasets/format/dataset_frame.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// The largest distance between two vertices (exact, quadratic in the vertex count).
double MeshDiameter(const TriangleMesh& mesh);

// Keys are obj_id in ascending order. InvalidArgument for obj_id 0, a repeated obj_id or a part
// without vertices.
StatusOr<std::string> ModelsInfoJson(const std::vector<PartModel>& parts);

}  // namespace vscan::service::dataset
