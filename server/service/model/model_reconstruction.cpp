#include "service/model/model_reconstruction.h"

#include <chrono>
#include <string>
#include <vector>

#include "reconstruction/poisson_pipeline.h"
#include "reconstruction/range_image.h"
#include "reconstruction/tsdf_fusion.h"
#include "service/model/model_scans.h"

namespace vscan::service {
namespace {

bool Stopped(const std::atomic<bool>* cancel) { return cancel && cancel->load(); }

StatusOr<TriangleMesh> Tsdf(const StoredClouds& clouds, const ServerOptions& server_options, const ModelPlan& plan,
                            const AlignedScans& aligned, const ModelCrop& crop, double voxel_size,
                            const std::atomic<bool>* cancel) {
  std::vector<reconstruction::RangeImage> images;
  for (size_t i = 0; i < aligned.scans.size(); ++i) {
    const ScanAlignmentRecord& record = aligned.scans[i];
    if (!record.aligned) continue;
    if (Stopped(cancel)) return Cancelled("model job stopped");
    ASSIGN_OR_RETURN(const ModelScan scan, LoadModelScan(clouds, plan, i, ModelCrop{}));
    if (!scan.camera || scan.pixels.size() != scan.points.size()) {
      return FailedPrecondition("reconstruction.method", "TSDF needs the camera and pixels of cloud '" +
                                                             scan.cloud_id + "'");
    }
    // Points the crop drops leave their pixels empty, so fusion carves there instead.
    PointCloud cloud;
    cloud.fields = kFieldPosition | kFieldPixel;
    const Eigen::Isometry3f model_from_sensor = record.model_from_sensor.cast<float>();
    for (size_t k = 0; k < scan.points.size(); ++k) {
      if (!crop.Contains(model_from_sensor * scan.points[k])) continue;
      cloud.positions.push_back(scan.points[k]);
      cloud.pixels.push_back(scan.pixels[k]);
    }
    ASSIGN_OR_RETURN(reconstruction::RangeImage image,
                     reconstruction::RangeImageFromScan(cloud, *scan.camera, record.model_from_sensor,
                                                        reconstruction::CloudFrame::kSensor));
    images.push_back(std::move(image));
  }
  if (Stopped(cancel)) return Cancelled("model job stopped");
  reconstruction::TsdfFusionOptions options;
  options.tsdf.voxel_size = static_cast<float>(voxel_size);
  options.tsdf.max_block_bytes = server_options.limits.max_request_memory_bytes;
  auto fused = reconstruction::FuseRangeImages(images, options, nullptr, cancel);
  if (fused.status().code() == StatusCode::kCancelled) return Cancelled("model job stopped");
  if (fused.status().code() == StatusCode::kResourceExhausted) {
    // The engine names its own option; the client set reconstruction.voxel_size, bounded by the flag.
    return ResourceExhausted("reconstruction.voxel_size",
                             std::string(fused.status().text()) + " (--max-request-memory-mib)");
  }
  return fused;
}

StatusOr<TriangleMesh> Poisson(const ServerOptions& server_options, const PlacedScans& placed, const ModelPlan& plan,
                               double voxel_size, const std::atomic<bool>* cancel) {
  std::vector<reconstruction::ScanPoints> scans;
  for (size_t k = 0; k < placed.points.size(); ++k) scans.push_back({placed.points[k], placed.origins[k]});
  reconstruction::PoissonPipelineOptions options;
  options.voxel_size = static_cast<float>(voxel_size);
  options.poisson.depth = static_cast<int>(plan.poisson_depth);
  options.helper_path = server_options.poisson_helper_path;
  options.max_memory_bytes = server_options.limits.max_request_memory_bytes;
  auto mesh = reconstruction::ReconstructPoisson(scans, options, nullptr, cancel);
  if (mesh.status().code() == StatusCode::kResourceExhausted) {
    // The engine names its own option; the client set reconstruction.poisson_depth.
    return ResourceExhausted("reconstruction.poisson_depth",
                             std::string(mesh.status().text()) + " (--max-request-memory-mib)");
  }
  if (mesh.status().code() == StatusCode::kCancelled) return Cancelled("model job stopped");
  return mesh;
}

}  // namespace

StatusOr<ModelMesh> ReconstructModel(const StoredClouds& clouds, const ServerOptions& options, const ModelPlan& plan,
                                     const AlignedScans& aligned, const PlacedScans& placed, const ModelCrop& crop,
                                     double voxel_size, const std::atomic<bool>* cancel) {
  const auto start = std::chrono::steady_clock::now();
  ModelMesh out;
  out.voxel_size = voxel_size;
  if (placed.total_points() == 0) return FailedPrecondition("reconstruct", "no aligned points to reconstruct from");
  TriangleMesh mesh;
  if (plan.reconstruction == ReconstructionKind::kTsdf) {
    out.method = "tsdf";
    ASSIGN_OR_RETURN(mesh, Tsdf(clouds, options, plan, aligned, crop, voxel_size, cancel));
  } else {
    out.method = "poisson";
    ASSIGN_OR_RETURN(mesh, Poisson(options, placed, plan, voxel_size, cancel));
  }
  if (Stopped(cancel)) return Cancelled("model job stopped");
  out.mesh = ClipMesh(mesh, crop);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace vscan::service
