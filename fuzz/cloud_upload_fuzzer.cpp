// libFuzzer target for a cloud upload as UploadCloud parses it (service::ParseUploadedCloud over
// the PLY and PCD readers) and stores it (EncodePly, read back by ParsePly when the cloud is
// loaded). The first byte picks the format the client named; the rest is the file. An accepted
// cloud must have consistent arrays, finite bounded positions and survive the store unchanged.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "service/clouds/cloud_import.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/physical_limits.h"

namespace {

using vscan::PointCloud;
using vscan::StatusCode;
using vscan::service::CloudFileFormat;

// Small enough that a fuzzing run never holds more than a few MiB per input.
constexpr uint64_t kMaxCloudBytes = uint64_t{4} << 20;

void Check(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "cloud_upload_fuzzer: %s\n", what);
  std::abort();
}

template <typename T>
void CheckSize(const std::vector<T>& values, bool present, size_t n, const char* what) {
  Check(values.size() == (present ? n : 0), what);
}

void CheckConsistent(const PointCloud& cloud) {
  const size_t n = cloud.size();
  Check(n > 0, "accepted cloud without points");
  Check(n * cloud.BytesPerPoint() <= kMaxCloudBytes, "accepted cloud beyond max_bytes");
  CheckSize(cloud.normals, cloud.Has(vscan::kFieldNormal), n, "normals do not match the fields");
  CheckSize(cloud.ranges, cloud.Has(vscan::kFieldRange), n, "ranges do not match the fields");
  CheckSize(cloud.intensities, cloud.Has(vscan::kFieldIntensity), n, "intensities do not match the fields");
  CheckSize(cloud.instance_ids, cloud.Has(vscan::kFieldInstanceId), n, "instances do not match the fields");
  CheckSize(cloud.pixels, cloud.Has(vscan::kFieldPixel), n, "pixels do not match the fields");
  CheckSize(cloud.clean_positions, cloud.Has(vscan::kFieldCleanPosition), n, "clean positions do not match");
  CheckSize(cloud.incidence_angles, cloud.Has(vscan::kFieldIncidence), n, "incidences do not match the fields");
  CheckSize(cloud.statuses, cloud.Has(vscan::kFieldStatus), n, "statuses do not match the fields");
  CheckSize(cloud.estimated_normals, cloud.Has(vscan::kFieldEstimatedNormal), n, "estimated normals do not match");
  for (const auto& p : cloud.positions) {
    Check(p.allFinite() && p.cwiseAbs().maxCoeff() <= vscan::kMaxCoordinateM, "accepted an unbounded position");
  }
}

// Bitwise, so that NaN values in the optional fields compare equal to themselves.
template <typename T>
bool SameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void CheckSame(const PointCloud& a, const PointCloud& b) {
  Check(a.fields == b.fields, "stored cloud lost or gained fields");
  Check(SameBytes(a.positions, b.positions) && SameBytes(a.normals, b.normals) && SameBytes(a.ranges, b.ranges) &&
            SameBytes(a.intensities, b.intensities) && SameBytes(a.instance_ids, b.instance_ids) &&
            SameBytes(a.pixels, b.pixels) && SameBytes(a.clean_positions, b.clean_positions) &&
            SameBytes(a.incidence_angles, b.incidence_angles) && SameBytes(a.statuses, b.statuses) &&
            SameBytes(a.estimated_normals, b.estimated_normals),
        "stored cloud reads back different values");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  constexpr CloudFileFormat kFormats[] = {CloudFileFormat::kDetect, CloudFileFormat::kPly, CloudFileFormat::kPcd};
  const CloudFileFormat format = kFormats[data[0] % 3];
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);

  const auto cloud = vscan::service::ParseUploadedCloud(bytes, format, kMaxCloudBytes);
  if (!cloud.ok()) {
    Check(cloud.status().code() == StatusCode::kInvalidArgument ||
              cloud.status().code() == StatusCode::kResourceExhausted,
          "upload refused with a code other than INVALID_ARGUMENT or RESOURCE_EXHAUSTED");
    return 0;
  }
  CheckConsistent(*cloud);
  const auto stored = vscan::EncodePly(*cloud);
  Check(stored.ok(), "an accepted cloud cannot be stored");
  const auto loaded = vscan::ParsePly(*stored, "stored cloud", ~uint64_t{0});
  Check(loaded.ok(), "a stored cloud cannot be read back");
  CheckSame(*cloud, *loaded);
  return 0;
}
