#pragma once
// The files `vscan localize` and `vscan score` read and write: a scan's ground truth
// (<cloud>.gt.json, as `vscan bin scan` writes it), pose estimates (estimates.json, or the BOP
// toolkit's results CSV) and part symmetries; and the ScorePosesRequest built from them.
// Formats: docs/LOCALIZATION.md, "Service and CLI".

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"
#include "vscan/v1/localization.pb.h"
#include "vscan/v1/scan.pb.h"

namespace vscan::cli {

struct GroundTruthFile {
  std::optional<Pose3> world_from_sensor;
  std::vector<v1::ObjectTruth> objects;
};

// One pose of a part: a mesh at a scale.
struct PoseRow {
  uint32_t part = 0;  // index into EstimatesFile::parts (0 where the file lists none)
  std::string mesh_id;
  double scale = 1;
  Pose3 world_from_part = Pose3::Identity();
  double score = 0;
  uint64_t explained_points = 0;
};

// A part a Localize call searched for, and how its search went.
struct SearchedPart {
  std::string mesh_id;
  double scale = 1;
  uint32_t max_instances = 0;  // 0: the options' default
  uint64_t found = 0;
  std::string stop_reason;
  double voxel_size = 0;
};

// What a Localize call found, as estimates.json holds it. Files written before parts were listed
// hold estimates only; they still read.
struct EstimatesFile {
  std::string cloud;  // the file or cloud id searched
  std::string frame = "world";
  double localize_ms = 0;
  std::vector<SearchedPart> parts;
  std::vector<PoseRow> estimates;
};

// Errors name the file and the entry ("a.gt.json: objects[3].world_from_object: ...").
StatusOr<GroundTruthFile> ReadGroundTruth(const std::string& path);
StatusOr<EstimatesFile> ReadEstimates(const std::string& path);
std::string EstimatesJson(const EstimatesFile& file);

// BOP results: header `scene_id,im_id,obj_id,score,R,t,time`, R nine row-major numbers and t three
// numbers in millimetres separated by spaces, camera_from_model; world_from_sensor takes them to
// the world. obj_ids maps BOP object ids to mesh ids (with their scale).
StatusOr<std::vector<PoseRow>> ReadBopResults(const std::string& path, const Pose3& world_from_sensor,
                                              const std::map<int, PoseRow>& obj_ids);

// {"<mesh_id>": {"continuous": [{"axis": [x,y,z], "point": [x,y,z]}], "discrete": [[16 values]]}}
// in the part's frame, metres.
StatusOr<std::map<std::string, v1::PartSymmetry>> ReadSymmetries(const std::string& path);

// The parts are the (mesh, scale) pairs searched (so a part searched for and never found still
// counts its true instances), then those the estimates name, in order of first appearance; the
// truth is every object of those parts (objects of other meshes, such as the bin, are left out).
v1::ScorePosesRequest BuildScoreRequest(const GroundTruthFile& truth, const std::vector<PoseRow>& estimates,
                                        const std::map<std::string, v1::PartSymmetry>& symmetries,
                                        const std::vector<SearchedPart>& searched = {});

}  // namespace vscan::cli
