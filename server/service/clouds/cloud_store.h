#pragma once
// Clouds as stored resources: an uploaded file checked and kept as canonical binary PLY (every
// field it carried, in the layout vscan writes) with its catalogue row; a cloud read back; an
// uploaded cloud deleted with the blob nothing else names. A campaign's scans become clouds where
// the job tracker records them.

#include <optional>
#include <string>
#include <string_view>

#include "sensor/camera.h"
#include "service/clouds/cloud_import.h"
#include "service/context/service_context.h"
#include "store/blob_gc.h"
#include "store/cloud_catalogue.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::service {

// What a client says about the cloud it uploads (checked against the contract already).
struct CloudUpload {
  std::string name;  // "cloud" when empty
  CloudFileFormat format = CloudFileFormat::kDetect;
  store::CloudFrame frame = store::CloudFrame::kWorld;
  std::optional<Pose3> world_from_sensor;
  std::optional<sensor::PinholeCamera> camera;  // lighting unused
  std::string scene_id;                         // empty: not scanned in a scene of this server
};

// Parses and checks bytes (ParseUploadedCloud, bounded by --max-upload-mib), then stores them.
// Errors name "cloud data", "format", "camera" or "scene_id" (NOT_FOUND for an unknown scene);
// a refused upload stores nothing.
StatusOr<store::CloudRecord> ImportCloud(ServiceContext& context, std::string_view bytes, const CloudUpload& upload);

struct StoredCloud {
  store::CloudRecord record;
  std::string ply;  // the binary PLY bytes, hash checked
};

// What reading a stored cloud needs: the clouds' rows and the blobs that hold their PLY bytes.
struct StoredClouds {
  store::CloudCatalogue& records;
  store::BlobStore& blobs;
};

inline StoredClouds StoredCloudsOf(ServiceContext& context) { return {context.clouds, context.blobs}; }

// NOT_FOUND naming cloud_id for an unknown cloud.
StatusOr<StoredCloud> LoadCloud(const StoredClouds& clouds, const std::string& cloud_id);

// Deletes an uploaded cloud and then its blob unless another row names it. NOT_FOUND for an
// unknown cloud, FAILED_PRECONDITION for a campaign's scan (it goes with its job).
StatusOr<store::CollectedBlobs> DeleteCloud(ServiceContext& context, const std::string& cloud_id);

// The row of the cloud a camera describes.
store::CloudCamera ToCloudCamera(const sensor::PinholeCamera& camera);

}  // namespace vscan::service
