#include "service/datasets/format/scene_json.h"

#include "service/job/json_writer.h"
#include "service/datasets/format/bop_units.h"

namespace vscan::service::dataset {
namespace {

void Rotation(JsonWriter& json, const Pose3& pose) {
  json.Open('[');
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) json.Value(pose.linear()(r, c));
  }
  json.Close(']');
}

void TranslationMm(JsonWriter& json, const Pose3& pose) {
  json.Vector(pose.translation() * kMillimetresPerMetre);
}

void Box(JsonWriter& json, const ImageBox& box) {
  json.Open('[');
  for (const int32_t v : {box.x, box.y, box.width, box.height}) {
    json.Value(double(v));
  }
  json.Close(']');
}

}  // namespace

std::string SceneCameraJson(const std::vector<ViewRecord>& views, double depth_scale_mm) {
  JsonWriter json;
  json.Open('{');
  for (size_t v = 0; v < views.size(); ++v) {
    const DatasetFrame& frame = views[v].frame;
    const CameraIntrinsics& k = frame.camera;
    const Pose3 camera_from_world = frame.world_from_camera.inverse();
    json.Key(std::to_string(v)).Open('{');
    // BOP and OpenCV put pixel (u, v)'s centre at (u, v), vscan at (u + 0.5, v + 0.5).
    const double cx = k.cx - 0.5, cy = k.cy - 0.5;
    json.Key("cam_K").Open('[');
    for (const double x : {k.fx, 0.0, cx, 0.0, k.fy, cy, 0.0, 0.0, 1.0}) json.Value(x);
    json.Close(']');
    json.Key("depth_scale").Value(depth_scale_mm);
    json.Key("width").Value(uint64_t{k.width});
    json.Key("height").Value(uint64_t{k.height});
    json.Key("cam_R_w2c");
    Rotation(json, camera_from_world);
    json.Key("cam_t_w2c");
    TranslationMm(json, camera_from_world);
    json.Key("world_from_camera").Matrix(frame.world_from_camera);
    json.Close('}');
  }
  json.Close('}');
  return json.str() + "\n";
}

std::string SceneGtJson(const std::vector<ViewRecord>& views) {
  JsonWriter json;
  json.Open('{');
  for (size_t v = 0; v < views.size(); ++v) {
    const DatasetFrame& frame = views[v].frame;
    const Pose3 camera_from_world = frame.world_from_camera.inverse();
    json.Key(std::to_string(v)).Open('[');
    for (const GroundTruthObject& object : frame.objects) {
      const Pose3 camera_from_object = camera_from_world * object.world_from_object;
      json.Open('{');
      json.Key("obj_id").Value(uint64_t{object.obj_id});
      json.Key("instance_id").Value(uint64_t{object.instance_id});
      json.Key("cam_R_m2c");
      Rotation(json, camera_from_object);
      json.Key("cam_t_m2c");
      TranslationMm(json, camera_from_object);
      json.Close('}');
    }
    json.Close(']');
  }
  json.Close('}');
  return json.str() + "\n";
}

std::string CameraParamsJson(const DatasetFrame& frame, double depth_scale_mm) {
  const CameraIntrinsics& k = frame.camera;
  JsonWriter json;
  json.Open('{');
  json.Key("cx").Value(k.cx - 0.5);
  json.Key("cy").Value(k.cy - 0.5);
  json.Key("depth_scale").Value(depth_scale_mm);
  json.Key("fx").Value(k.fx);
  json.Key("fy").Value(k.fy);
  json.Key("height").Value(uint64_t{k.height});
  json.Key("width").Value(uint64_t{k.width});
  json.Close('}');
  return json.str() + "\n";
}

std::string SceneFillJson(const DatasetFrame& frame) {
  JsonWriter json;
  json.Open('{');
  json.Key("parts_planned").Value(frame.parts_planned);
  json.Key("parts_placed").Value(frame.parts_placed);
  json.Key("underfilled").Value(frame.parts_placed < frame.parts_planned);
  json.Key("mesh_overlap").Open('{');
  json.Key("max_part_part_m").Value(frame.deepest_part_overlap_m);
  json.Key("max_part_bin_m").Value(frame.deepest_bin_overlap_m);
  json.Close('}');
  json.Close('}');
  return json.str() + "\n";
}

bool SceneFillSaysUnderfilled(std::string_view bytes) {
  return bytes.find("\"underfilled\":true") != std::string_view::npos;
}

std::string SceneGtInfoJson(const std::vector<ViewRecord>& views) {
  JsonWriter json;
  json.Open('{');
  for (size_t v = 0; v < views.size(); ++v) {
    const DatasetFrame& frame = views[v].frame;
    const std::vector<VisibleStats>& visible = views[v].visible;
    json.Key(std::to_string(v)).Open('[');
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      json.Open('{');
      json.Key("bbox_obj");
      Box(json, frame.objects[i].full_box);
      json.Key("bbox_visib");
      Box(json, visible[i].box);
      json.Key("px_count_all").Value(frame.objects[i].alone_pixels);
      json.Key("px_count_valid").Value(visible[i].with_depth);
      json.Key("px_count_visib").Value(visible[i].pixels);
      json.Key("visib_fract").Value(frame.objects[i].visible_fraction);
      json.Close('}');
    }
    json.Close(']');
  }
  json.Close('}');
  return json.str() + "\n";
}

}  // namespace vscan::service::dataset
