#include "service/clouds/cloud_store.h"

#include <algorithm>
#include <cstdint>
#include <utility>

#include "vscan/common/cloud_io.h"
#include "vscan/common/physical_limits.h"

namespace vscan::service {

store::CloudCamera ToCloudCamera(const sensor::PinholeCamera& camera) {
  return {camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy, camera.near, camera.far};
}

StatusOr<store::CloudRecord> ImportCloud(ServiceContext& context, std::string_view bytes, const CloudUpload& upload) {
  const uint64_t limit = context.options.limits.max_upload_bytes;
  if (bytes.size() > limit) {
    return ResourceExhausted(std::string(kCloudDataField), std::to_string(bytes.size()) +
                                                               " bytes exceed the upload limit of " +
                                                               std::to_string(limit) + " (--max-upload-mib)");
  }
  if (upload.camera) RETURN_IF_ERROR(sensor::ValidateCamera(*upload.camera, "camera", UINT64_MAX));
  if (upload.world_from_sensor) {
    RETURN_IF_ERROR(CheckPosition(upload.world_from_sensor->translation(), "world_from_sensor"));
  }
  if (!upload.scene_id.empty()) {
    const auto scene = context.registry.catalogue().GetScene(upload.scene_id);
    if (!scene.ok()) {
      if (scene.status().code() == StatusCode::kNotFound) {
        return NotFound("scene_id", "no scene '" + upload.scene_id + "'");
      }
      return scene.status();
    }
  }
  // The parsed arrays are what this request holds in memory.
  const Limits& limits = context.options.limits;
  ASSIGN_OR_RETURN(PointCloud cloud,
                   ParseUploadedCloud(bytes, upload.format, std::min(limit, limits.max_request_memory_bytes)));
  if (cloud.size() > limits.max_cloud_points) {
    return ResourceExhausted(std::string(kCloudDataField), std::to_string(cloud.size()) +
                                                               " points exceed the limit of " +
                                                               std::to_string(limits.max_cloud_points) +
                                                               " (--max-cloud-points)");
  }
  ASSIGN_OR_RETURN(const std::string ply, EncodePly(cloud));

  store::CloudRecord record;
  record.name = upload.name.empty() ? "cloud" : upload.name;
  record.size_bytes = ply.size();
  record.points = cloud.size();
  record.fields = cloud.fields;
  record.origin = store::CloudOrigin::kUploaded;
  record.scene_id = upload.scene_id;
  record.frame = upload.frame;
  if (upload.world_from_sensor) record.world_from_sensor = upload.world_from_sensor->matrix();
  if (upload.camera) record.camera = ToCloudCamera(*upload.camera);
  cloud = PointCloud();
  // Pinned until the row names it, so that a concurrent delete of the same bytes cannot collect it.
  const std::string storing = "storing cloud '" + record.name + "': ";
  auto pin = context.blobs.PutPinned(ply);
  if (!pin.ok()) return Status(pin.status().code(), storing + pin.status().message());
  record.sha256 = pin->sha256();
  auto inserted = context.clouds.Insert(std::move(record));
  if (!inserted.ok()) return Status(inserted.status().code(), storing + inserted.status().message());
  return inserted;
}

StatusOr<StoredCloud> LoadCloud(const StoredClouds& clouds, const std::string& cloud_id) {
  StoredCloud stored;
  ASSIGN_OR_RETURN(stored.record, clouds.records.Get(cloud_id));
  ASSIGN_OR_RETURN(stored.ply, clouds.blobs.Get(stored.record.sha256));
  return stored;
}

StatusOr<store::CollectedBlobs> DeleteCloud(ServiceContext& context, const std::string& cloud_id) {
  ASSIGN_OR_RETURN(const std::string sha256, context.clouds.Delete(cloud_id));
  return store::CollectBlobs(context.clouds.database(), context.blobs, {sha256});
}

}  // namespace vscan::service
