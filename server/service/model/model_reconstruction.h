#pragma once
// The reconstruction stage of a model job: TSDF fusion of the scans' range images rebuilt at their
// aligned poses when every scan has a camera and pixels, else screened Poisson over the placed
// union; the mesh is cut to the crop.

#include <atomic>
#include <string>

#include "service/model/model_alignment.h"
#include "service/model/model_crop.h"
#include "service/model/model_plan.h"
#include "service/model/model_union.h"
#include "service/clouds/cloud_store.h"
#include "service/context/server_options.h"
#include "vscan/common/mesh.h"

namespace vscan::service {

struct ModelMesh {
  TriangleMesh mesh;  // model frame
  std::string method;  // "tsdf" or "poisson"
  double voxel_size = 0;
  double seconds = 0;
};

// voxel_size > 0. CANCELLED when cancel becomes true (checked between scans and stages).
// TSDF reads the scans again from clouds; options bound the memory and name the Poisson helper.
StatusOr<ModelMesh> ReconstructModel(const StoredClouds& clouds, const ServerOptions& options, const ModelPlan& plan,
                                     const AlignedScans& aligned, const PlacedScans& placed, const ModelCrop& crop,
                                     double voxel_size, const std::atomic<bool>* cancel);

}  // namespace vscan::service
