#pragma once
// Writes one scene directory (docs/DATASETS.md, "A scene"): everything goes into
// train_pbr/<id>.partial first and is renamed to train_pbr/<id> once complete and flushed, so a scene
// directory either is whole or does not exist.

#include <filesystem>
#include <vector>

#include "service/datasets/format/dataset_frame.h"
#include "service/datasets/format/dataset_plan.h"
#include "service/datasets/format/scene_json.h"
#include "service/datasets/format/scene_record.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// One scene written view by view: each view's images and cloud as it comes, the JSON files and the
// record once the plan's views.count views are in. The plan must outlive the writer.
class SceneWriter {
 public:
  // Replaces a leftover partial directory of this scene; AlreadyExists when the scene is written.
  static StatusOr<SceneWriter> Begin(const std::filesystem::path& root, const DatasetPlan& plan, const SceneKey& key);
  // InvalidArgument for a frame CheckFrame refuses, OutOfRange for a depth beyond 16 bits,
  // FailedPrecondition past the plan's views.
  Status AddView(const DatasetFrame& frame);
  // FailedPrecondition unless every view is in; then the scene is renamed into place.
  Status Finish();

 private:
  SceneWriter(const std::filesystem::path& root, const DatasetPlan& plan, const SceneKey& key);
  // Writes a file of the scene durably and remembers it for the record.
  Status Write(const std::string& relative, std::string_view bytes);
  Status WriteEncoded(const std::string& relative, const StatusOr<std::string>& bytes);

  std::filesystem::path final_dir_;
  std::filesystem::path partial_;
  const DatasetPlan* plan_;
  SceneKey key_;
  std::vector<ViewRecord> views_;
  std::vector<SceneFileEntry> written_;
};

// A scene of one view (a plan whose views.count is 1): Begin, AddView, Finish.
Status WriteScene(const std::filesystem::path& root, const DatasetPlan& plan, const SceneKey& key,
                  const DatasetFrame& frame);

}  // namespace vscan::service::dataset
