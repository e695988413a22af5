#include "service/datasets/format/scene_writer.h"

#include <algorithm>
#include <vector>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/durable_file.h"
#include "service/datasets/format/scene_images.h"
#include "service/datasets/format/scene_pickable_json.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/png_codec.h"

namespace vscan::service::dataset {
namespace {

constexpr const char* kImageDirs[] = {"depth", "gray", "reasons", "mask", "mask_visib", "instances", "cloud"};

// Positions, and normals and instance ids when the cloud has them: the fields the layout promises.
PointCloud LayoutCloud(const PointCloud& cloud) {
  PointCloud out;
  out.fields = kFieldPosition | (cloud.fields & (kFieldNormal | kFieldInstanceId));
  out.positions = cloud.positions;
  if (out.Has(kFieldNormal)) out.normals = cloud.normals;
  if (out.Has(kFieldInstanceId)) out.instance_ids = cloud.instance_ids;
  return out;
}

Status MakeDirectories(const std::filesystem::path& partial) {
  std::error_code ec;
  std::filesystem::remove_all(partial, ec);
  if (ec) return Internal("cannot remove " + partial.string() + ": " + ec.message());
  for (const char* sub : kImageDirs) {
    std::filesystem::create_directories(partial / sub, ec);
    if (ec) return Internal("cannot create " + (partial / sub).string() + ": " + ec.message());
  }
  return Status::Ok();
}

// The frame as the scene's JSON files need it: no images, cloud or masks.
DatasetFrame Header(const DatasetFrame& frame) {
  DatasetFrame header;
  header.camera = frame.camera;
  header.world_from_camera = frame.world_from_camera;
  header.objects = frame.objects;
  for (GroundTruthObject& object : header.objects) object.alone_mask = {};
  header.parts_planned = frame.parts_planned;
  header.parts_placed = frame.parts_placed;
  header.deepest_part_overlap_m = frame.deepest_part_overlap_m;
  header.deepest_bin_overlap_m = frame.deepest_bin_overlap_m;
  header.materials = frame.materials;
  header.picks = frame.picks;
  return header;
}

}  // namespace

SceneWriter::SceneWriter(const std::filesystem::path& root, const DatasetPlan& plan, const SceneKey& key)
    : final_dir_(SceneDir(root, key.scene_id)), partial_(PartialSceneDir(root, key.scene_id)), plan_(&plan), key_(key) {}

StatusOr<SceneWriter> SceneWriter::Begin(const std::filesystem::path& root, const DatasetPlan& plan,
                                         const SceneKey& key) {
  SceneWriter writer(root, plan, key);
  std::error_code ec;
  if (std::filesystem::exists(writer.final_dir_, ec)) {
    return Status(StatusCode::kAlreadyExists, writer.final_dir_.string() + " is already written");
  }
  RETURN_IF_ERROR(MakeDirectories(writer.partial_));
  return writer;
}

Status SceneWriter::Write(const std::string& relative, std::string_view bytes) {
  RETURN_IF_ERROR(WriteFileDurably(partial_ / relative, bytes));
  written_.push_back({relative, bytes.size(), Crc32(bytes)});
  return Status::Ok();
}

Status SceneWriter::WriteEncoded(const std::string& relative, const StatusOr<std::string>& bytes) {
  if (!bytes.ok()) return bytes.status();
  return Write(relative, std::string_view(*bytes));
}

Status SceneWriter::AddView(const DatasetFrame& frame) {
  if (views_.size() >= plan_->views.count) {
    return FailedPrecondition(final_dir_.string() + ": the plan has " + std::to_string(plan_->views.count) +
                              " views per scene, this would be one more");
  }
  RETURN_IF_ERROR(CheckFrame(frame));
  const uint32_t width = frame.camera.width, height = frame.camera.height;
  const std::string image = SixDigits(views_.size());
  ASSIGN_OR_RETURN(const std::vector<uint16_t> depth, QuantizeDepth(frame, plan_->depth_scale_mm));
  const std::vector<uint16_t> object_index = ObjectIndexImage(frame);
  RETURN_IF_ERROR(WriteEncoded("depth/" + image + ".png", EncodeGray16Png(width, height, depth)));
  RETURN_IF_ERROR(WriteEncoded("instances/" + image + ".png", EncodeGray16Png(width, height, object_index)));
  if (!frame.gray.empty()) {
    RETURN_IF_ERROR(WriteEncoded("gray/" + image + ".png", EncodeGray16Png(width, height, frame.gray)));
  }
  if (!frame.reasons.empty()) {
    RETURN_IF_ERROR(WriteEncoded("reasons/" + image + ".png", EncodeGray8Png(width, height, frame.reasons)));
  }
  for (size_t i = 0; i < frame.objects.size(); ++i) {
    RETURN_IF_ERROR(WriteEncoded("mask_visib/" + image + "_" + SixDigits(i) + ".png",
                                 EncodeGray8Png(width, height, VisibleMask(object_index, i))));
    RETURN_IF_ERROR(WriteEncoded("mask/" + image + "_" + SixDigits(i) + ".png",
                                 EncodeGray8Png(width, height, AloneMask(frame.objects[i], width * height))));
  }
  RETURN_IF_ERROR(WriteEncoded("cloud/" + image + ".ply", EncodePly(LayoutCloud(frame.cloud))));
  views_.push_back({Header(frame), VisibleStatsOf(object_index, depth, width, frame.objects.size())});
  return Status::Ok();
}

Status SceneWriter::Finish() {
  if (views_.size() != plan_->views.count) {
    return FailedPrecondition(final_dir_.string() + ": " + std::to_string(views_.size()) + " of " +
                              std::to_string(plan_->views.count) + " views written");
  }
  RETURN_IF_ERROR(Write("scene_camera.json", SceneCameraJson(views_, plan_->depth_scale_mm)));
  RETURN_IF_ERROR(Write("scene_gt.json", SceneGtJson(views_)));
  RETURN_IF_ERROR(Write("scene_gt_info.json", SceneGtInfoJson(views_)));
  RETURN_IF_ERROR(Write(kSceneFillFile, SceneFillJson(views_.front().frame)));
  if (const auto& materials = views_.front().frame.materials) {
    RETURN_IF_ERROR(Write(kSceneMaterialsFile, SceneMaterialsJson(*materials)));
  }
  if (views_.front().frame.picks) {
    RETURN_IF_ERROR(WriteEncoded(kScenePickableFile, ScenePickableJson(views_.front().frame)));
  }
  std::vector<SceneFileEntry> files = written_;
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  RETURN_IF_ERROR(Write(kSceneRecordFile, SceneRecordJson(*plan_, key_, files)));
  for (const char* sub : kImageDirs) RETURN_IF_ERROR(SyncDirectory(partial_ / sub));
  RETURN_IF_ERROR(SyncDirectory(partial_));
  return RenameDurably(partial_, final_dir_);
}

Status WriteScene(const std::filesystem::path& root, const DatasetPlan& plan, const SceneKey& key,
                  const DatasetFrame& frame) {
  ASSIGN_OR_RETURN(SceneWriter writer, SceneWriter::Begin(root, plan, key));
  RETURN_IF_ERROR(writer.AddView(frame));
  return writer.Finish();
}

}  // namespace vscan::service::dataset
