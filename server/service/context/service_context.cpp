#include "service/context/service_context.h"

#include "collision/collision_world.h"
#include "localization/part_model_cache.h"

namespace vscan::service {

namespace {
constexpr size_t kCachedShapes = 512;
// A cell works with a few parts; a part model is 10-20 MiB for the fixture parts and up to about
// 300 MiB at the pair table's bound, so the models kept are bounded by bytes too.
constexpr size_t kCachedPartModels = 8;
constexpr size_t kCachedPartModelBytes = size_t{512} << 20;
}

ServiceContext::ServiceContext(scenes::SceneRegistry& registry, jobs::WorkerPool& workers,
                               jobs::WorkerPool& call_workers, const ServerOptions& options,
                               robot_registry::RobotRegistry& robots, RasterProvider& raster,
                               store::CloudCatalogue& clouds, store::BlobStore& blobs)
    : registry(registry), workers(workers), call_workers(call_workers), options(options), robots(robots), raster(raster),
      clouds(clouds), blobs(blobs), scans(options.limits.max_concurrent_scans),
      shapes(std::make_shared<collision::ShapeCache>(kCachedShapes)),
      part_models(std::make_shared<localization::PartModelCache>(kCachedPartModels, kCachedPartModelBytes)) {}

ServiceContext::~ServiceContext() = default;

}  // namespace vscan::service
