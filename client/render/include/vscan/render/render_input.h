#pragma once
// What `vscan render` draws, read from a file: a point cloud (.pcd, or .ply without faces) or a
// triangle mesh (.obj, .stl, or .ply with faces). Coordinates are used as stored.

#include <optional>
#include <string>

#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"
#include "vscan/render/view.h"

namespace vscan::render {

enum class InputKind { kCloud, kMesh };

// INVALID_ARGUMENT naming INPUT for an extension other than .ply, .pcd, .obj, .stl.
StatusOr<InputKind> InputKindOf(const std::string& path);

struct RenderInput {
  InputKind kind = InputKind::kCloud;
  PointCloud cloud;   // kCloud
  TriangleMesh mesh;  // kMesh
  Bounds bounds;      // of the finite positions or vertices
  size_t Count() const { return kind == InputKind::kCloud ? cloud.size() : mesh.triangles.size(); }
};

// NOT_FOUND, INVALID_ARGUMENT or DATA_LOSS naming the file when it cannot be read, is malformed, or
// holds nothing to draw.
StatusOr<RenderInput> LoadRenderInput(const std::string& path);

}  // namespace vscan::render
