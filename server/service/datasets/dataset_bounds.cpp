#include "service/datasets/dataset_bounds.h"

#include <algorithm>
#include <string>

namespace vscan::service {
namespace {

// A binary PLY: float x y z per vertex, a uchar count and three ints per triangle, and its header.
uint64_t ModelPlyBytes(const TriangleMesh& mesh) {
  return 256 + 12 * uint64_t{mesh.vertices.size()} + 13 * uint64_t{mesh.triangles.size()};
}

}  // namespace

uint64_t DatasetViewsPerScene(const dataset::DatasetPlan& plan) { return plan.views.count; }

uint64_t DatasetImageCount(const dataset::DatasetPlan& plan) {
  return dataset::SceneCount(plan) * DatasetViewsPerScene(plan);
}

uint64_t DatasetImageBytes(uint64_t width, uint64_t height) { return width * height * kDatasetBytesPerPixel; }

uint64_t DatasetTarBound(uint64_t max_request_memory_bytes) {
  return max_request_memory_bytes == 0 ? kMaxTarArtifactBytes : std::min(kMaxTarArtifactBytes, max_request_memory_bytes);
}

DatasetBytes EstimateDatasetBytes(const DatasetSetup& setup, uint64_t max_tar_bytes) {
  const dataset::DatasetPlan& plan = setup.plan;
  // Scenes are (seed, bin, sensor): each sensor sees seeds x bins scenes.
  const uint64_t images_per_sensor =
      uint64_t{plan.seeds.size()} * plan.bins.size() * DatasetViewsPerScene(plan);
  DatasetBytes bytes;
  for (const DatasetSensorSetup& sensor : setup.sensors) {
    bytes.directory += images_per_sensor * DatasetImageBytes(sensor.camera.width, sensor.camera.height);
  }
  for (const dataset::PartModel& part : setup.parts) bytes.directory += ModelPlyBytes(part.mesh);
  if (bytes.directory <= max_tar_bytes) bytes.tar = bytes.directory;
  return bytes;
}

Status CheckDatasetScenes(const dataset::DatasetPlan& plan, uint64_t max_scenes) {
  const uint64_t scenes = dataset::SceneCount(plan);
  if (scenes <= max_scenes) return Status::Ok();
  return ResourceExhausted("seeds", "seeds x bins x sensors make " + std::to_string(scenes) + " scenes (" +
                                        std::to_string(DatasetImageCount(plan)) +
                                        " images); this server takes at most " + std::to_string(max_scenes) +
                                        " in one plan (--max-dataset-scenes)");
}

}  // namespace vscan::service
