#pragma once
// One captured view as the dataset writer takes it: the camera, its depth and instance images, the
// cloud, and the true pose of every part in the bin. Producers (the bin scan) fill it; the writer
// turns it into a scene directory (docs/DATASETS.md).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "service/datasets/format/dataset_materials.h"

namespace vscan::service::dataset {

// Pinhole intrinsics in pixels; pixel (u, v) has its centre at (u + 0.5, v + 0.5) as in OpenCV.
struct CameraIntrinsics {
  double fx = 0;
  double fy = 0;
  double cx = 0;
  double cy = 0;
  uint32_t width = 0;
  uint32_t height = 0;
};

// A pixel rectangle as BOP's calc_2d_bbox makes it: left column, top row, and width and height as
// max - min of the covered columns and rows (a one-pixel part has width 0); [-1, -1, 0, 0] when empty.
struct ImageBox {
  int32_t x = -1;
  int32_t y = -1;
  int32_t width = 0;
  int32_t height = 0;
};

struct GroundTruthObject {
  uint32_t obj_id = 0;       // part type, 1-based: the key of models_info.json
  uint32_t instance_id = 0;  // the value this part has in the instance image and the cloud
  Pose3 world_from_object = Pose3::Identity();
  double visible_fraction = 0;  // visible pixels over the pixels of the part alone in the view
  uint64_t visible_pixels = 0;  // must equal its pixel count in the instance image
  uint64_t alone_pixels = 0;    // pixels of the part alone in the view (BOP's px_count_all)
  std::vector<uint32_t> alone_mask;  // v * width + u of those pixels: BOP's mask/ (may be left empty)
  ImageBox full_box;            // the box of the part alone in the view (occlusion ignored); width 0 when outside
};

// Whether the plan's robot can pick one placed part (scene_pickable.json).
struct PartPickRecord {
  uint32_t instance_id = 0;
  bool pickable = false;
  std::string failure;  // the PickFailure's API name, "PICK_FAILURE_UNSPECIFIED" when pickable
  std::string detail;
  std::optional<size_t> grasp;               // index into its part type's grasps, best first
  Pose3 world_from_tool = Pose3::Identity();  // with grasp: the tool at it, world frame
  std::optional<uint32_t> covered_by_instance;  // covered by another part
  bool covered_by_bin = false;                  // covered by the bin (or the table under it)
};

struct DatasetFrame {
  CameraIntrinsics camera;
  Pose3 world_from_camera = Pose3::Identity();  // camera axes: x right, y down, z forward
  // Row-major width * height: depth along the optical axis in metres, 0 or NaN where nothing was measured.
  std::vector<float> depth_m;
  // Row-major width * height: the instance seen at each pixel, 0 for none.
  std::vector<uint32_t> instance_ids;
  // Row-major width * height, or empty (not written): each pixel's PointStatus (0 where the ray met
  // no surface) and the grey image (docs/SENSORS.md, "Per-pixel images").
  std::vector<uint8_t> reasons;
  std::vector<uint16_t> gray;
  PointCloud cloud;  // world frame; positions, and normals and instance ids when present are written
  std::vector<GroundTruthObject> objects;
  // The bin's fill: parts it asked for and parts that settled in it (fewer when the bin was full).
  uint64_t parts_planned = 0;
  uint64_t parts_placed = 0;
  // How deep the settled parts' own meshes overlap each other and the bin (metres, measured on the
  // true meshes, not the collision shapes).
  double deepest_part_overlap_m = 0;
  double deepest_bin_overlap_m = 0;
  // Set when the plan gives any part a material: each placed part's (scene_materials.json).
  std::optional<std::vector<InstanceMaterial>> materials;
  // Set when the plan checks picks: one per placed part, shared by every view of the fill.
  std::shared_ptr<const std::vector<PartPickRecord>> picks;
};

// A part type for models/models_info.json.
struct PartModel {
  uint32_t obj_id = 0;
  TriangleMesh mesh;  // metres, in the part's own frame
  std::vector<Pose3> discrete_symmetries;  // object_from_object transforms that leave the part unchanged
  struct ContinuousSymmetry {
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();  // a point on the axis
  };
  std::vector<ContinuousSymmetry> continuous_symmetries;
};

}  // namespace vscan::service::dataset
