#pragma once
// The JSON files of one scene in BOP's form: each maps the image id ("0", "1", ... one per view) to
// the camera, the ground-truth poses, or what each ground-truth object shows. Poses in
// millimetres, rotations as row-major 3x3 lists.

#include <string>
#include <string_view>
#include <vector>

#include "service/datasets/format/dataset_frame.h"
#include "service/datasets/format/scene_images.h"

namespace vscan::service::dataset {

// What a scene's JSON files hold of one view: the frame without its images, cloud and masks, and
// what each ground-truth object shows in it.
struct ViewRecord {
  DatasetFrame frame;
  std::vector<VisibleStats> visible;
};

// Per view: cam_K (pixel centres at whole coordinates, as BOP and OpenCV have them: the frame's cx - 0.5),
// depth_scale, width, height, cam_R_w2c, cam_t_w2c and world_from_camera (row-major 4x4, metres).
std::string SceneCameraJson(const std::vector<ViewRecord>& views, double depth_scale_mm);
// Per view: obj_id, instance_id, cam_R_m2c, cam_t_m2c per object, in the frame's order.
std::string SceneGtJson(const std::vector<ViewRecord>& views);
// Per view: bbox_obj, bbox_visib, px_count_all, px_count_valid, px_count_visib, visib_fract per object.
std::string SceneGtInfoJson(const std::vector<ViewRecord>& views);
// BOP's camera.json: cx, cy (as in cam_K), depth_scale, fx, fy, height, width.
std::string CameraParamsJson(const DatasetFrame& frame, double depth_scale_mm);
// parts_planned, parts_placed and underfilled (fewer placed than planned): vscan's, not BOP's.
std::string SceneFillJson(const DatasetFrame& frame);
// Whether a scene_fill.json's bytes say the bin was underfilled.
bool SceneFillSaysUnderfilled(std::string_view bytes);

}  // namespace vscan::service::dataset
