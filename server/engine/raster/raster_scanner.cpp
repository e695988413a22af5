#include "raster/raster_scanner.h"

#include <chrono>
#include <memory>
#include <string>

#include "raster/frame_decode.h"
#include "raster/frame_render.h"
#include "raster/render_state.h"

namespace vscan::raster {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

bool IsCancelled(const RasterOptions& options) {
  return options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed);
}

Status CheckFrameSize(const sensor::PinholeCamera& camera, uint32_t max_side) {
  const std::string limit = ": at most " + std::to_string(max_side) + " pixels for the raster backend";
  if (camera.width > max_side) return ResourceExhausted("camera.width" + limit);
  if (camera.height > max_side) return ResourceExhausted("camera.height" + limit);
  return Status::Ok();
}

// What the render thread hands back besides the pixels.
struct Rendered {
  RenderedFrame frame;
  ViewPlanes planes;
  std::shared_ptr<const SceneFaces> faces;
  bool uploaded = false;
  double upload_ms = 0, render_ms = 0;
};

StatusOr<DecodedFrame> Scan(RasterRenderer& renderer, const std::string& scene_key,
                            std::span<const raycast::SceneInstance> instances, const sensor::PinholeCamera& camera,
                            const Pose3& world_from_sensor, RasterMethod method, const RasterOptions& options,
                            const DirectLight* light, RasterStats* stats) {
  const auto start = Clock::now();
  RETURN_IF_ERROR(sensor::ValidateCamera(camera, "camera", options.max_pixels));
  RETURN_IF_ERROR(CheckFrameSize(camera, renderer.max_side()));
  if (!world_from_sensor.matrix().allFinite()) return InvalidArgument("world_from_sensor: NaN or infinite value");
  if (IsCancelled(options)) return Cancelled("scan cancelled");

  Rendered rendered;
  RETURN_IF_ERROR(renderer.Run([&](RenderState& state) -> Status {
    if (IsCancelled(options)) return Cancelled("scan cancelled");
    ASSIGN_OR_RETURN(const SceneLookup scene, state.scenes.Acquire(scene_key, instances));
    rendered.faces = scene.faces;
    rendered.uploaded = scene.uploaded;
    rendered.upload_ms = scene.upload_ms;
    rendered.planes = PlanesForScene(camera, world_from_sensor, scene.faces->world_box, options.hug_scene_bounds);
    if (rendered.planes.empty) return Status::Ok();

    const auto render_start = Clock::now();
    FrameRequest request;
    request.camera = &camera;
    request.world_from_sensor = world_from_sensor;
    request.scene_centre = scene.faces->centre;
    request.planes = rendered.planes;
    request.method = method;
    request.depth_format = options.depth_format;
    request.direct_light = light;
    RETURN_IF_ERROR(RenderFrame(state, *scene.gpu, request, rendered.frame));
    rendered.render_ms = MsSince(render_start);
    return Status::Ok();
  }));

  const auto decode_start = Clock::now();
  DecodeRequest request;
  request.camera = &camera;
  request.world_from_sensor = world_from_sensor;
  request.planes = rendered.planes;
  request.method = method;
  request.depth_format = options.depth_format;
  request.fields = options.fields;
  request.sensor_frame = options.frame == raycast::ScanFrame::kSensor;
  request.cancel = options.cancel;
  ASSIGN_OR_RETURN(DecodedFrame decoded, DecodeFrame(rendered.frame, *rendered.faces, request));

  if (stats != nullptr) {
    stats->pixels = camera.pixel_count();
    stats->points = decoded.cloud.size();
    stats->min_range = decoded.min_range;
    stats->max_range = decoded.max_range;
    stats->near = rendered.planes.near;
    stats->far = rendered.planes.far;
    stats->near_range = rendered.planes.near_range;
    stats->far_range = rendered.planes.far_range;
    stats->scene_uploaded = rendered.uploaded;
    stats->upload_ms = rendered.upload_ms;
    stats->render_ms = rendered.render_ms;
    stats->decode_ms = MsSince(decode_start);
    stats->elapsed_ms = MsSince(start);
  }
  return decoded;
}

}  // namespace

StatusOr<PointCloud> RasterScan(RasterRenderer& renderer, const std::string& scene_key,
                                std::span<const raycast::SceneInstance> instances,
                                const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                                RasterMethod method, const RasterOptions& options, RasterStats* stats) {
  ASSIGN_OR_RETURN(DecodedFrame decoded,
                   Scan(renderer, scene_key, instances, camera, world_from_sensor, method, options, nullptr, stats));
  return std::move(decoded.cloud);
}

StatusOr<LitCloud> RasterScanLit(RasterRenderer& renderer, const std::string& scene_key,
                                 std::span<const raycast::SceneInstance> instances,
                                 const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                                 RasterMethod method, const DirectLight& light, const RasterOptions& options,
                                 RasterStats* stats) {
  ASSIGN_OR_RETURN(DecodedFrame decoded,
                   Scan(renderer, scene_key, instances, camera, world_from_sensor, method, options, &light, stats));
  LitCloud out{std::move(decoded.cloud), std::move(decoded.direct_radiance)};
  // A frame whose planes hug nothing renders nothing, and so has no radiance either.
  out.direct_radiance.resize(out.cloud.size(), 0.0f);
  return out;
}

}  // namespace vscan::raster
