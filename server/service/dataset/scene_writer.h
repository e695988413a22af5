#pragma once
// Writes one scene directory (docs/DATASETS.md, "A scene"): everything goes into
// train_pbr/<id>.partial first and is renamed to train_pbr/<id> once complete and flushed, so a scene
// directory either is whole or does not exist.

#include <filesystem>

#include "service/dataset/dataset_frame.h"
#include "service/dataset/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// Replaces a leftover partial directory of this scene. InvalidArgument for a frame CheckFrame
// refuses, OutOfRange for a depth beyond 16 bits, AlreadyExists when the scene is already there.
Status WriteScene(const std::filesystem::path& root, const DatasetPlan& plan, const SceneKey& key,
                  const DatasetFrame& frame);

}  // namespace vscan::service::dataset
