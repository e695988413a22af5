#pragma once
// A point cloud file written block by block as the points arrive (the binary PLY or PCD of
// cloud_io.h): into a temporary file beside the destination, renamed into place when finished,
// so that a reader never sees a partial file and a failed scan leaves none.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan {

enum class CloudFileFormat { kPly, kPcd };

// From a path's extension (.ply or .pcd, any case).
std::optional<CloudFileFormat> CloudFileFormatOf(const std::string& path);

class CloudFileWriter {
 public:
  // When points is not known, the header keeps room for the count (padding in a comment) and
  // Finish writes it.
  static StatusOr<CloudFileWriter> Open(const std::string& path, CloudFileFormat format, uint32_t fields,
                                        std::optional<uint64_t> points = std::nullopt);
  CloudFileWriter(CloudFileWriter&&) noexcept;
  CloudFileWriter& operator=(CloudFileWriter&&) noexcept;
  // An unfinished file is removed.
  ~CloudFileWriter();

  // Appends every point of block, whose fields must be the ones given to Open.
  Status Append(const PointCloud& block);
  // Writes the count, syncs and renames the file into place.
  Status Finish();
  uint64_t points() const;

 private:
  struct State;
  explicit CloudFileWriter(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace vscan
