#include "service/datasets/dataset_scoring.h"

#include <algorithm>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>

#include "geometry/mesh_import.h"
#include "service/datasets/format/model_ply.h"

namespace vscan::service {
namespace {

// Per object: its model as ScoreScan takes it, and the vertex operations one pair costs.
struct ScoredModel {
  localization::PartDefinition part;
  uint64_t pair_work = 0;
  // With a gripper: the model in metres, and its grasps once an image needs them.
  std::optional<TriangleMesh> mesh_m;
  std::optional<PartGraspJudge> grasp_judge;
};

constexpr double kMetresPerMillimetre = 0.001;

// The model's triangles in metres (models/obj_<obj_id>.ply is in millimetres).
StatusOr<TriangleMesh> ReadModelMeshMetres(const std::filesystem::path& root, uint32_t obj_id) {
  const std::filesystem::path path = root / dataset::ModelPlyPath(obj_id);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in) return DataLoss(path.string() + ": cannot be read");
  StatusOr<TriangleMesh> mesh =
      geometry::ImportMesh(bytes.view(), geometry::MeshFileFormat::kPly, kMetresPerMillimetre);
  if (!mesh.ok()) return DataLoss(path.string() + ": " + mesh.status().message());
  return mesh;
}

Pose3 InMetres(Pose3 pose) {
  pose.translation() *= kMetresPerMillimetre;
  return pose;
}

uint64_t PairWork(const localization::PartDefinition& part) {
  constexpr uint64_t kAddSWorkPerVertex = 20;  // the k-d tree ADD-S builds and searches
  const uint64_t transforms =
      std::max<size_t>(1, localization::SymmetryTransforms(part.symmetries, localization::kBopSymmetryStep).size());
  return part.vertices.size() * (transforms + (part.symmetries.any() ? kAddSWorkPerVertex : 1));
}

std::string KnownIds(const std::map<uint32_t, DatasetModel>& models) {
  std::string ids;
  for (const auto& [obj_id, model] : models) {
    if (ids.size() > 80) return ids + ", ...";
    ids += (ids.empty() ? "" : ", ") + std::to_string(obj_id);
  }
  return ids.empty() ? "none" : ids;
}

bool IsCancelled(const DatasetScoringOptions& options) {
  return options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed);
}

}  // namespace

StatusOr<DatasetScore> ScoreDatasetResults(const std::filesystem::path& root,
                                           std::span<const dataset::BopResultRow> rows,
                                           const DatasetScoringOptions& options, std::string_view field) {
  localization::ScoringOptions scoring;  // BOP's: visib_gt_min 0.1, ADD(-S) at 0.1, n_top = -1
  scoring.cancel = options.cancel;
  DatasetScore out;
  out.mssd_thresholds = localization::BopMssdThresholds();
  out.add_threshold = scoring.add_threshold;
  out.min_visible_fraction = scoring.min_visible_fraction;
  out.tally = DatasetScoreTally(out.mssd_thresholds.size(), options.max_scenes);
  out.rows = rows.size();
  ASSIGN_OR_RETURN(out.scene_count, ReadDatasetSceneCount(root));
  ASSIGN_OR_RETURN(out.models, ReadDatasetModels(root));
  for (const dataset::BopResultRow& row : rows) {
    if (!out.models.contains(row.obj_id)) {
      return InvalidArgument(std::string(field), "line " + std::to_string(row.line) + ", column 3 (obj_id): obj_id " +
                                                     std::to_string(row.obj_id) +
                                                     " is not a part type of the dataset (models_info.json has " +
                                                     KnownIds(out.models) + ")");
    }
  }
  for (const auto& [obj_id, model] : out.models) out.tally.AddObject(obj_id);

  // Rows by image, in file order within an image (ties in score keep it, as Python's sort does).
  std::vector<size_t> order(rows.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::pair(rows[a].scene_id, rows[a].im_id) < std::pair(rows[b].scene_id, rows[b].im_id);
  });
  std::vector<bool> used(rows.size(), false);
  std::map<uint32_t, ScoredModel> loaded;

  for (uint64_t scene = 0; scene < out.scene_count; ++scene) {
    if (IsCancelled(options)) return Cancelled("scoring cancelled");
    const auto scene_id = static_cast<uint32_t>(scene);
    out.tally.AddScene(scene_id);
    ASSIGN_OR_RETURN(const SceneTruth truth, ReadSceneTruth(root, scene));
    for (const auto& [im_id, objects] : truth) {
      ++out.images;
      out.true_instances += objects.size();
      // This image's rows: a contiguous run of order.
      const auto first = std::lower_bound(order.begin(), order.end(), std::pair(scene_id, im_id),
                                          [&](size_t i, const std::pair<uint32_t, uint32_t>& key) {
                                            return std::pair(rows[i].scene_id, rows[i].im_id) < key;
                                          });
      auto last = first;
      while (last != order.end() && rows[*last].scene_id == scene_id && rows[*last].im_id == im_id) {
        used[*last] = true;
        ++last;
      }
      std::map<uint32_t, size_t> valid;
      for (const TrueObject& object : objects) {
        if (!out.models.contains(object.obj_id)) {
          return DataLoss("scene " + std::to_string(scene) + " image " + std::to_string(im_id) + ": obj_id " +
                          std::to_string(object.obj_id) + " has no model in models_info.json");
        }
        if (object.visib_fract >= scoring.min_visible_fraction) ++valid[object.obj_id];
      }
      std::map<uint32_t, std::vector<size_t>> estimates_of;
      for (auto it = first; it != last; ++it) estimates_of[rows[*it].obj_id].push_back(*it);
      for (const auto& [obj_id, list] : estimates_of) out.tally.AddEstimates(scene_id, obj_id, list.size());
      if (valid.empty()) continue;

      std::vector<localization::PartDefinition> parts;
      std::vector<ScoredModel*> models_of_parts;
      std::vector<localization::TrueInstance> truths;
      std::vector<localization::EstimatedInstance> estimates;
      uint64_t work = 0;
      for (const auto& [obj_id, count] : valid) {
        auto model = loaded.find(obj_id);
        if (model == loaded.end()) {
          ScoredModel scored;
          scored.part.part_id = obj_id;
          ASSIGN_OR_RETURN(scored.part.vertices, ReadModelVertices(root, obj_id));
          scored.part.symmetries = out.models.at(obj_id).symmetries;
          // BOP's scripts divide the errors by models_info.json's diameter.
          scored.part.known_diameter = out.models.at(obj_id).diameter_mm;
          scored.pair_work = PairWork(scored.part);
          model = loaded.emplace(obj_id, std::move(scored)).first;
        }
        parts.push_back(model->second.part);
        models_of_parts.push_back(&model->second);
        // The best-scored n of the object's estimates, n its valid instances (BOP's n_top = -1).
        std::vector<size_t>& list = estimates_of[obj_id];
        std::stable_sort(list.begin(), list.end(), [&](size_t a, size_t b) { return rows[a].score > rows[b].score; });
        if (list.size() > count) list.resize(count);
        for (const size_t i : list) {
          localization::EstimatedInstance estimate;
          estimate.part_id = obj_id;
          estimate.world_from_part.linear() = rows[i].camera_R_model;
          estimate.world_from_part.translation() = rows[i].camera_t_model_mm;
          estimate.score = rows[i].score;
          estimates.push_back(estimate);
        }
        work += static_cast<uint64_t>(list.size()) * count * model->second.pair_work;
        if (options.grasp && !list.empty()) {
          ScoredModel& scored = model->second;
          if (!scored.mesh_m) {
            ASSIGN_OR_RETURN(scored.mesh_m, ReadModelMeshMetres(root, obj_id));
            work += GraspPreparationWork(*scored.mesh_m, *options.grasp);
          }
          work += static_cast<uint64_t>(list.size()) * GraspJudgementWork(*scored.mesh_m, *options.grasp);
        }
      }
      for (const TrueObject& object : objects) {
        if (!valid.contains(object.obj_id)) continue;
        localization::TrueInstance instance;
        instance.part_id = object.obj_id;
        instance.world_from_part = object.camera_from_model;
        instance.visible_fraction = object.visib_fract;
        truths.push_back(instance);
      }
      out.work += work;
      if (out.work > options.max_work) {
        return ResourceExhausted(std::string(field),
                                 "scoring the estimates against the dataset takes more than the " +
                                     std::to_string(options.max_work / 1000000) +
                                     " million vertex operations one call may take (reached at scene " +
                                     std::to_string(scene) + "); score a smaller dataset");
      }
      ASSIGN_OR_RETURN(const localization::ScanScore score, localization::ScoreScan(parts, truths, estimates, scoring));
      if (!options.grasp) {
        out.tally.AddImage(scene_id, score);
        continue;
      }
      std::vector<const PartGraspJudge*> judges(parts.size(), nullptr);
      for (size_t p = 0; p < parts.size(); ++p) {
        ScoredModel& scored = *models_of_parts[p];
        if (!scored.mesh_m) continue;  // no estimate of it yet: nothing to judge
        if (!scored.grasp_judge) {
          if (IsCancelled(options)) return Cancelled("scoring cancelled");
          auto judge = PartGraspJudge::Make(*scored.mesh_m, *options.grasp);
          if (!judge.ok() && judge.status().field() == "mesh") {
            return judge.status().WithFieldPrefix("obj_id " + std::to_string(scored.part.part_id));
          }
          if (!judge.ok()) return judge.status();
          scored.grasp_judge = std::move(*judge);
        }
        judges[p] = &*scored.grasp_judge;
      }
      for (localization::TrueInstance& t : truths) t.world_from_part = InMetres(t.world_from_part);
      for (localization::EstimatedInstance& e : estimates) e.world_from_part = InMetres(e.world_from_part);
      ASSIGN_OR_RETURN(const ScanGraspScore grasps, JudgeScanGrasps(score, judges, truths, estimates, options.cancel));
      out.tally.AddImage(scene_id, score, &grasps);
    }
  }
  for (const size_t i : order) {
    if (used[i]) continue;
    ++out.ignored_rows;
    const std::pair image(rows[i].scene_id, rows[i].im_id);
    if (out.ignored_images.size() < kMaxIgnoredImagesNamed &&
        (out.ignored_images.empty() || out.ignored_images.back() != image)) {
      out.ignored_images.push_back(image);
    }
  }
  return out;
}

}  // namespace vscan::service
