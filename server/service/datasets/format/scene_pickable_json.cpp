#include "service/datasets/format/scene_pickable_json.h"

#include <limits>
#include <map>

#include "service/datasets/format/bop_units.h"
#include "service/job/json_writer.h"

namespace vscan::service::dataset {

StatusOr<std::string> ScenePickableJson(const DatasetFrame& frame) {
  if (!frame.picks) return Internal("scene_pickable.json: the frame has no picks");
  std::map<uint32_t, const PartPickRecord*> by_instance;
  for (const PartPickRecord& record : *frame.picks) by_instance.emplace(record.instance_id, &record);
  std::map<uint32_t, size_t> gt_index;  // instance -> its place in scene_gt.json
  for (size_t i = 0; i < frame.objects.size(); ++i) gt_index.emplace(frame.objects[i].instance_id, i);
  JsonWriter json;
  json.Open('[');
  for (const GroundTruthObject& object : frame.objects) {
    const auto found = by_instance.find(object.instance_id);
    if (found == by_instance.end()) {
      return Internal("scene_pickable.json: no pick verdict for instance " + std::to_string(object.instance_id));
    }
    const PartPickRecord& pick = *found->second;
    json.Open('{');
    json.Key("obj_id").Value(uint64_t{object.obj_id});
    json.Key("instance_id").Value(uint64_t{object.instance_id});
    json.Key("pickable").Value(pick.pickable);
    json.Key("failure").Value(pick.failure);
    json.Key("detail").Value(pick.detail);
    json.Key("grasp");
    if (pick.grasp) {
      json.Open('{');
      json.Key("index").Value(uint64_t{*pick.grasp});
      json.Key("world_R_tool").Open('[');
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) json.Value(pick.world_from_tool.linear()(r, c));
      }
      json.Close(']');
      json.Key("world_t_tool").Vector(pick.world_from_tool.translation() * kMillimetresPerMetre);
      json.Close('}');
    } else {
      json.Value(std::numeric_limits<double>::quiet_NaN());  // the writer's null
    }
    // The covering part's index in scene_gt.json, -1 for none (or for the bin: covered_by_bin).
    double covered_by = -1;
    if (pick.covered_by_instance) {
      const auto cover = gt_index.find(*pick.covered_by_instance);
      if (cover != gt_index.end()) covered_by = double(cover->second);
    }
    json.Key("covered_by").Value(covered_by);
    json.Key("covered_by_bin").Value(pick.covered_by_bin);
    json.Close('}');
  }
  json.Close(']');
  return json.str() + "\n";
}

}  // namespace vscan::service::dataset
