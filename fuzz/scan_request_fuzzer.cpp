// libFuzzer target for a Scan request: the real request parsing (ParseScanRequest) and, when it
// accepts, the real scan (PrepareScanTarget + RunScanBackend, ray casting) over a small prepared
// scene. The input is a ScanRequest in protobuf text format; its ids are replaced by the prepared
// scene's, so that mutations explore the numbers. A refused request must carry a proper error
// code; an accepted one must scan without aborting and return only finite values.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <type_traits>
#include <vector>

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include "api/scan/scan_request.h"
#include "scan_fuzz_world.h"
#include "service/scan/scan_backends.h"
#include "service/scan/scan_target.h"

namespace {

using vscan::PointCloud;
using vscan::Status;
using vscan::StatusCode;
using vscan::fuzz::ScanFuzzWorld;

// SCAN_FUZZ_VERBOSE=1 prints what became of each input (for checking seeds by hand).
const bool kVerbose = std::getenv("SCAN_FUZZ_VERBOSE") != nullptr;

void Report(const char* stage, const Status& status) {
  if (kVerbose) std::fprintf(stderr, "  %s: %s\n", stage, status.ToString().c_str());
}

void Check(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "scan_request_fuzzer: %s\n", what);
  std::abort();
}

// Errors a client may get for a bad request; INTERNAL and UNKNOWN mean the server lost its way.
void CheckProperError(const Status& status, const char* stage) {
  if (status.code() != StatusCode::kInternal && status.code() != StatusCode::kUnknown &&
      status.code() != StatusCode::kOk) {
    return;
  }
  std::fprintf(stderr, "scan_request_fuzzer: %s: improper error %s\n", stage, status.ToString().c_str());
  std::abort();
}

class Silent : public google::protobuf::io::ErrorCollector {
 public:
  void AddError(int, google::protobuf::io::ColumnNumber, const std::string&) override {}
};

bool ParseText(const uint8_t* data, size_t size, vscan::v1::ScanRequest& request) {
  Silent silent;
  google::protobuf::TextFormat::Parser parser;
  parser.RecordErrorsTo(&silent);
  return parser.ParseFromString(std::string(reinterpret_cast<const char*>(data), size), &request);
}

void PointTo(const ScanFuzzWorld& world, vscan::v1::ScanRequest& request) {
  request.set_scene_id(world.scene_id);
  if (request.placement_case() == vscan::v1::ScanRequest::kRobot) {
    const auto named = world.mounts.find(request.robot().mount_id());
    request.mutable_robot()->set_mount_id(named != world.mounts.end() ? named->second : world.default_mount);
  }
}

template <typename T>
bool AllFinite(const std::vector<T>& values) {
  for (const T& v : values) {
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(v)) return false;
    } else if (!v.allFinite()) {
      return false;
    }
  }
  return true;
}

template <typename T>
bool Sized(const PointCloud& cloud, vscan::PointFields field, const std::vector<T>& values) {
  return values.size() == (cloud.Has(field) ? cloud.size() : 0);
}

void CheckCloud(const PointCloud& cloud, const vscan::service::ScanPlan& plan) {
  using namespace vscan;
  Check(Sized(cloud, kFieldNormal, cloud.normals) && Sized(cloud, kFieldRange, cloud.ranges) &&
            Sized(cloud, kFieldIntensity, cloud.intensities) && Sized(cloud, kFieldInstanceId, cloud.instance_ids) &&
            Sized(cloud, kFieldPixel, cloud.pixels) && Sized(cloud, kFieldCleanPosition, cloud.clean_positions) &&
            Sized(cloud, kFieldIncidence, cloud.incidence_angles) && Sized(cloud, kFieldStatus, cloud.statuses) &&
            Sized(cloud, kFieldEstimatedNormal, cloud.estimated_normals),
        "a field's array does not match the point count");
  Check(AllFinite(cloud.positions), "non-finite position");
  Check(AllFinite(cloud.normals), "non-finite normal");
  Check(AllFinite(cloud.ranges), "non-finite range");
  Check(AllFinite(cloud.intensities), "non-finite intensity");
  Check(AllFinite(cloud.clean_positions), "non-finite clean position");
  Check(AllFinite(cloud.incidence_angles), "non-finite incidence angle");
  Check(AllFinite(cloud.estimated_normals), "non-finite estimated normal");
  for (uint32_t pixel : cloud.pixels) Check(pixel < plan.camera.pixel_count(), "pixel index outside the image");
  for (uint8_t status : cloud.statuses) Check(status >= 1 && status <= 8, "unknown point status");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  vscan::fuzz::World();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vscan::v1::ScanRequest request;
  if (!ParseText(data, size, request)) return 0;
  ScanFuzzWorld& world = vscan::fuzz::World();
  PointTo(world, request);

  auto plan = vscan::api::ParseScanRequest(request, world.options.limits, *world.robots);
  if (!plan.ok()) {
    Report("ParseScanRequest", plan.status());
    CheckProperError(plan.status(), "ParseScanRequest");
    return 0;
  }
  // No EGL here: the raster backends scan by ray casting instead.
  plan->backend = vscan::service::ScanBackend::kRaycast;
  auto target = vscan::service::PrepareScanTarget(*world.context, *plan);
  if (!target.ok()) {
    Report("PrepareScanTarget", target.status());
    CheckProperError(target.status(), "PrepareScanTarget");
    return 0;
  }
  vscan::raycast::ScanStats stats;
  vscan::capture::MeasureStats measure;
  auto cloud = vscan::service::RunScanBackend(*plan, *target, world.raster, nullptr, &stats, &measure);
  if (!cloud.ok()) {
    Report("RunScanBackend", cloud.status());
    CheckProperError(cloud.status(), "RunScanBackend");
    return 0;
  }
  Check(cloud->size() <= plan->camera.pixel_count(), "more points than rays");
  CheckCloud(*cloud, *plan);
  if (kVerbose) std::fprintf(stderr, "  %zu points of %llu rays\n", cloud->size(),
                             static_cast<unsigned long long>(plan->camera.pixel_count()));
  return 0;
}
