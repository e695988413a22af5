#include "service/datasets/dataset_truth.h"

#include <cmath>
#include <exception>
#include <string>

#include <yaml-cpp/yaml.h>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/durable_file.h"
#include "service/datasets/format/model_ply.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {
namespace {

namespace fs = std::filesystem;

// The dataset's JSON files are YAML too: yaml-cpp reads them.
StatusOr<YAML::Node> ReadJson(const fs::path& path) {
  StatusOr<std::string> text = dataset::ReadWholeFile(path);
  if (!text.ok()) return DataLoss(path.string() + ": " + text.status().message());
  try {
    YAML::Node node = YAML::Load(*text);
    if (!node.IsMap()) return DataLoss(path.string() + ": not a JSON object");
    return node;
  } catch (const std::exception& e) {
    return DataLoss(path.string() + ": not JSON: " + e.what());
  }
}

// Every value read goes through these; a wrong type or a missing key throws, caught per file.
double Number(const YAML::Node& node) {
  const double value = node.as<double>();
  if (!std::isfinite(value)) throw YAML::Exception(node.Mark(), "not a finite number");
  return value;
}

uint32_t Id(const std::string& key) {
  size_t end = 0;
  const unsigned long value = std::stoul(key, &end);
  if (end != key.size() || value > 0xFFFFFFFFul) throw YAML::Exception(YAML::Mark(), "bad id '" + key + "'");
  return static_cast<uint32_t>(value);
}

Eigen::Vector3d Vector3(const YAML::Node& node) {
  if (!node.IsSequence() || node.size() != 3) throw YAML::Exception(node.Mark(), "expected 3 numbers");
  return {Number(node[0]), Number(node[1]), Number(node[2])};
}

Pose3 PoseOf(const YAML::Node& rotation, const YAML::Node& translation) {
  if (!rotation.IsSequence() || rotation.size() != 9) throw YAML::Exception(rotation.Mark(), "expected 9 numbers");
  Pose3 pose = Pose3::Identity();
  for (size_t i = 0; i < 9; ++i) pose.linear()(static_cast<int>(i / 3), static_cast<int>(i % 3)) = Number(rotation[i]);
  pose.translation() = Vector3(translation);
  return pose;
}

}  // namespace

StatusOr<uint64_t> ReadDatasetSceneCount(const fs::path& root) {
  std::error_code ec;
  if (!fs::exists(root / dataset::kSceneIndexFile, ec)) {
    return FailedPrecondition("the dataset has no " + std::string(dataset::kSceneIndexFile) +
                              ": it is not finished (merged)");
  }
  const fs::path path = root / dataset::kManifestFile;
  ASSIGN_OR_RETURN(const YAML::Node manifest, ReadJson(path));
  try {
    return manifest["scene_count"].as<uint64_t>();
  } catch (const std::exception& e) {
    return DataLoss(path.string() + ": scene_count: " + e.what());
  }
}

StatusOr<std::map<uint32_t, DatasetModel>> ReadDatasetModels(const fs::path& root) {
  const fs::path path = root / dataset::kModelsInfoFile;
  ASSIGN_OR_RETURN(const YAML::Node info, ReadJson(path));
  std::map<uint32_t, DatasetModel> models;
  try {
    for (const auto& entry : info) {
      DatasetModel model;
      model.obj_id = Id(entry.first.as<std::string>());
      const YAML::Node& fields = entry.second;
      model.diameter_mm = Number(fields["diameter"]);
      if (!(model.diameter_mm > 0)) throw YAML::Exception(fields.Mark(), "diameter must be positive");
      if (const YAML::Node discrete = fields["symmetries_discrete"]) {
        for (const YAML::Node& m : discrete) {
          if (!m.IsSequence() || m.size() != 16) throw YAML::Exception(m.Mark(), "expected 16 numbers");
          Eigen::Matrix4d matrix;
          for (size_t i = 0; i < 16; ++i) matrix(static_cast<int>(i / 4), static_cast<int>(i % 4)) = Number(m[i]);
          Pose3 symmetry = Pose3::Identity();
          symmetry.matrix() = matrix;
          model.symmetries.discrete.push_back(symmetry);
        }
      }
      if (const YAML::Node continuous = fields["symmetries_continuous"]) {
        for (const YAML::Node& axis : continuous) {
          localization::ContinuousSymmetry symmetry;
          symmetry.axis = Vector3(axis["axis"]);
          if (!(symmetry.axis.norm() > 0)) throw YAML::Exception(axis.Mark(), "a zero axis");
          symmetry.axis.normalize();
          symmetry.point = Vector3(axis["offset"]);
          model.symmetries.continuous.push_back(symmetry);
        }
      }
      models[model.obj_id] = std::move(model);
    }
  } catch (const std::exception& e) {
    return DataLoss(path.string() + ": " + e.what());
  }
  return models;
}

StatusOr<std::vector<Eigen::Vector3f>> ReadModelVertices(const fs::path& root, uint32_t obj_id) {
  const fs::path path = root / dataset::ModelPlyPath(obj_id);
  StatusOr<PointCloud> cloud = ReadPly(path.string());
  if (!cloud.ok()) return DataLoss(path.string() + ": " + cloud.status().message());
  if (cloud->positions.empty()) return DataLoss(path.string() + ": no vertices");
  for (const Eigen::Vector3f& v : cloud->positions) {
    if (!v.allFinite()) return DataLoss(path.string() + ": a vertex is not finite");
  }
  return std::move(cloud->positions);
}

StatusOr<SceneTruth> ReadSceneTruth(const fs::path& root, uint64_t scene_id) {
  const fs::path dir = dataset::SceneDir(root, scene_id);
  const fs::path gt_path = dir / "scene_gt.json", info_path = dir / "scene_gt_info.json";
  ASSIGN_OR_RETURN(const YAML::Node gt, ReadJson(gt_path));
  ASSIGN_OR_RETURN(const YAML::Node info, ReadJson(info_path));
  SceneTruth truth;
  const fs::path* reading = &gt_path;
  try {
    for (const auto& image : gt) {
      const uint32_t im_id = Id(image.first.as<std::string>());
      std::vector<TrueObject>& objects = truth[im_id];
      for (const YAML::Node& object : image.second) {
        TrueObject out;
        out.obj_id = object["obj_id"].as<uint32_t>();
        out.camera_from_model = PoseOf(object["cam_R_m2c"], object["cam_t_m2c"]);
        objects.push_back(out);
      }
    }
    reading = &info_path;
    for (auto& [im_id, objects] : truth) {
      const YAML::Node stats = info[std::to_string(im_id)];
      if (!stats.IsSequence() || stats.size() != objects.size()) {
        throw YAML::Exception(stats.Mark(), "image " + std::to_string(im_id) + " does not list one entry per object of scene_gt.json");
      }
      for (size_t i = 0; i < objects.size(); ++i) {
        const double fraction = Number(stats[i]["visib_fract"]);
        if (!(fraction >= 0 && fraction <= 1)) throw YAML::Exception(stats[i].Mark(), "visib_fract outside [0, 1]");
        objects[i].visib_fract = fraction;
      }
    }
  } catch (const std::exception& e) {
    return DataLoss(reading->string() + ": " + e.what());
  }
  return truth;
}

}  // namespace vscan::service
