#pragma once
// A part's mesh as BOP's models/obj_<obj_id>.ply: binary little-endian, float x y z in
// millimetres, triangles as "list uchar int vertex_indices" (what bop_toolkit's inout.load_ply reads).

#include <string>

#include "service/datasets/format/dataset_frame.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// "models/obj_000001.ply" for obj_id 1.
std::string ModelPlyPath(uint32_t obj_id);

// InvalidArgument naming parts[i] when the mesh is empty or a triangle indexes past its vertices.
StatusOr<std::string> EncodeModelPly(const PartModel& part);

}  // namespace vscan::service::dataset
