#include "service/dataset/scene_writer.h"

#include <algorithm>
#include <vector>

#include "service/dataset/dataset_layout.h"
#include "service/dataset/durable_file.h"
#include "service/dataset/scene_images.h"
#include "service/dataset/scene_json.h"
#include "service/dataset/scene_record.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/png_codec.h"

namespace vscan::service::dataset {
namespace {

// The image id inside a scene; one image per scene.
constexpr const char* kImage = "000000";

// Writes files under one directory and remembers each for the record.
class SceneFiles {
 public:
  explicit SceneFiles(std::filesystem::path dir) : dir_(std::move(dir)) {}

  Status Write(const std::string& relative, std::string_view bytes) {
    RETURN_IF_ERROR(WriteFileDurably(dir_ / relative, bytes));
    written_.push_back({relative, bytes.size(), Crc32(bytes)});
    return Status::Ok();
  }
  Status WriteEncoded(const std::string& relative, const StatusOr<std::string>& bytes) {
    if (!bytes.ok()) return bytes.status();
    return Write(relative, std::string_view(*bytes));
  }
  std::vector<SceneFileEntry> Sorted() const {
    std::vector<SceneFileEntry> files = written_;
    std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
    return files;
  }

 private:
  std::filesystem::path dir_;
  std::vector<SceneFileEntry> written_;
};

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
  for (const char* sub : {"depth", "mask", "mask_visib", "instances", "cloud"}) {
    std::filesystem::create_directories(partial / sub, ec);
    if (ec) return Internal("cannot create " + (partial / sub).string() + ": " + ec.message());
  }
  return Status::Ok();
}

Status WriteSceneFiles(const DatasetPlan& plan, const SceneKey& key, const DatasetFrame& frame, SceneFiles& files) {
  const uint32_t width = frame.camera.width, height = frame.camera.height;
  ASSIGN_OR_RETURN(const std::vector<uint16_t> depth, QuantizeDepth(frame, plan.depth_scale_mm));
  const std::vector<uint16_t> object_index = ObjectIndexImage(frame);
  const std::vector<VisibleStats> visible = VisibleStatsOf(object_index, depth, width, frame.objects.size());
  RETURN_IF_ERROR(files.Write("scene_camera.json", SceneCameraJson(frame, plan.depth_scale_mm)));
  RETURN_IF_ERROR(files.Write("scene_gt.json", SceneGtJson(frame)));
  RETURN_IF_ERROR(files.Write("scene_gt_info.json", SceneGtInfoJson(frame, visible)));
  RETURN_IF_ERROR(files.Write(kSceneFillFile, SceneFillJson(frame)));
  RETURN_IF_ERROR(files.WriteEncoded(std::string("depth/") + kImage + ".png", EncodeGray16Png(width, height, depth)));
  RETURN_IF_ERROR(
      files.WriteEncoded(std::string("instances/") + kImage + ".png", EncodeGray16Png(width, height, object_index)));
  for (size_t i = 0; i < frame.objects.size(); ++i) {
    const std::string name = std::string("mask_visib/") + kImage + "_" + SixDigits(i) + ".png";
    RETURN_IF_ERROR(files.WriteEncoded(name, EncodeGray8Png(width, height, VisibleMask(object_index, i))));
    const std::string full = std::string("mask/") + kImage + "_" + SixDigits(i) + ".png";
    RETURN_IF_ERROR(files.WriteEncoded(full, EncodeGray8Png(width, height, AloneMask(frame.objects[i], width * height))));
  }
  RETURN_IF_ERROR(files.WriteEncoded(std::string("cloud/") + kImage + ".ply", EncodePly(LayoutCloud(frame.cloud))));
  return files.Write(kSceneRecordFile, SceneRecordJson(plan, key, files.Sorted()));
}

}  // namespace

Status WriteScene(const std::filesystem::path& root, const DatasetPlan& plan, const SceneKey& key,
                  const DatasetFrame& frame) {
  RETURN_IF_ERROR(CheckFrame(frame));
  const std::filesystem::path final_dir = SceneDir(root, key.scene_id);
  std::error_code ec;
  if (std::filesystem::exists(final_dir, ec)) {
    return Status(StatusCode::kAlreadyExists, final_dir.string() + " is already written");
  }
  const std::filesystem::path partial = PartialSceneDir(root, key.scene_id);
  RETURN_IF_ERROR(MakeDirectories(partial));
  SceneFiles files(partial);
  RETURN_IF_ERROR(WriteSceneFiles(plan, key, frame, files));
  for (const char* sub : {"depth", "mask", "mask_visib", "instances", "cloud"}) RETURN_IF_ERROR(SyncDirectory(partial / sub));
  RETURN_IF_ERROR(SyncDirectory(partial));
  return RenameDurably(partial, final_dir);
}

}  // namespace vscan::service::dataset
