#include "raycast/raycast_scene.h"

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "raycast/embree_scene.h"

namespace vscan::raycast {
namespace {

const char* ErrorName(RTCError error) {
  switch (error) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

// One device for the process: creating a device spins up Embree's thread pool and ISA dispatch.
StatusOr<RTCDevice> SharedDevice() {
  static const std::pair<RTCDevice, RTCError> device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    return std::make_pair(d, d == nullptr ? rtcGetDeviceError(nullptr) : RTC_ERROR_NONE);
  }();
  if (device.first == nullptr) {
    return Internal(std::string("Embree device creation failed: ") + ErrorName(device.second));
  }
  return device.first;
}

std::string InstanceField(size_t i) { return "instances[" + std::to_string(i) + "]"; }

Status CheckInstance(const SceneInstance& instance, size_t i) {
  if (instance.mesh == nullptr) return InvalidArgument(InstanceField(i) + ".mesh: missing");
  if (!std::isfinite(instance.scale) || instance.scale <= 0) {
    return InvalidArgument(InstanceField(i) + ".scale: must be finite and positive");
  }
  if (!instance.world_from_object.matrix().allFinite()) {
    return InvalidArgument(InstanceField(i) + ".world_from_object: NaN or infinite value");
  }
  const TriangleMesh& mesh = *instance.mesh;
  if (mesh.vertices.size() > std::numeric_limits<uint32_t>::max() ||
      mesh.triangles.size() > std::numeric_limits<uint32_t>::max()) {
    return InvalidArgument(InstanceField(i) + ".mesh: more than 2^32 vertices or triangles");
  }
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!mesh.vertices[v].allFinite()) {
      return InvalidArgument(InstanceField(i) + ".mesh.vertices[" + std::to_string(v) + "]: NaN or infinite value");
    }
  }
  const auto vertex_count = static_cast<uint32_t>(mesh.vertices.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (uint32_t index : mesh.triangles[t]) {
      if (index >= vertex_count) {
        return InvalidArgument(InstanceField(i) + ".mesh.triangles[" + std::to_string(t) + "]: vertex index " +
                               std::to_string(index) + " out of range (" + std::to_string(vertex_count) +
                               " vertices)");
      }
    }
  }
  return Status::Ok();
}

// Writes the instance's world-frame vertices and triangles into a new Embree geometry.
StatusOr<RTCGeometry> MakeGeometry(RTCDevice device, const SceneInstance& instance, size_t i) {
  const TriangleMesh& mesh = *instance.mesh;
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (geometry == nullptr) return Internal("Embree: cannot create a triangle geometry");
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                                 RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                                                 mesh.triangles.size()));
  if (vertices == nullptr || indices == nullptr) {
    rtcReleaseGeometry(geometry);
    return Internal("Embree: cannot allocate geometry buffers");
  }
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Eigen::Vector3d w = instance.world_from_object * (instance.scale * mesh.vertices[v].cast<double>());
    const Eigen::Vector3f wf = w.cast<float>();
    if (!wf.allFinite()) {
      rtcReleaseGeometry(geometry);
      return InvalidArgument(InstanceField(i) + ": vertex " + std::to_string(v) + " is not finite in the world frame");
    }
    vertices[3 * v] = wf.x();
    vertices[3 * v + 1] = wf.y();
    vertices[3 * v + 2] = wf.z();
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = mesh.triangles[t][k];
  }
  rtcCommitGeometry(geometry);
  return geometry;
}

}  // namespace

RaycastScene::RaycastScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RaycastScene::~RaycastScene() = default;

StatusOr<std::shared_ptr<const RaycastScene>> RaycastScene::Build(std::span<const SceneInstance> instances) {
  for (size_t i = 0; i < instances.size(); ++i) RETURN_IF_ERROR(CheckInstance(instances[i], i));
  ASSIGN_OR_RETURN(RTCDevice device, SharedDevice());

  auto impl = std::make_unique<Impl>();
  rtcRetainDevice(device);
  impl->device = device;
  rtcGetDeviceError(device);  // clears a stale error left on this thread
  impl->scene = rtcNewScene(device);
  if (impl->scene == nullptr) return Internal("Embree: cannot create a scene");
  rtcSetSceneFlags(impl->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl->scene, RTC_BUILD_QUALITY_HIGH);

  for (size_t i = 0; i < instances.size(); ++i) {
    if (instances[i].mesh->empty()) continue;
    ASSIGN_OR_RETURN(RTCGeometry geometry, MakeGeometry(device, instances[i], i));
    const uint32_t geom_id = rtcAttachGeometry(impl->scene, geometry);
    rtcReleaseGeometry(geometry);
    if (geom_id == RTC_INVALID_GEOMETRY_ID) return Internal("Embree: cannot attach a geometry");
    if (impl->instance_of_geometry.size() <= geom_id) impl->instance_of_geometry.resize(geom_id + 1, 0);
    impl->instance_of_geometry[geom_id] = instances[i].instance_id;
    impl->triangles += instances[i].mesh->triangles.size();
  }
  rtcCommitScene(impl->scene);
  if (const RTCError error = rtcGetDeviceError(device); error != RTC_ERROR_NONE) {
    return Internal(std::string("Embree scene build failed: ") + ErrorName(error));
  }
  return std::shared_ptr<const RaycastScene>(new RaycastScene(std::move(impl)));
}

uint64_t RaycastScene::triangle_count() const { return impl_->triangles; }

uint32_t RaycastScene::InstanceOfGeometry(uint32_t geom_id) const {
  const auto& table = impl_->instance_of_geometry;
  return geom_id < table.size() ? table[geom_id] : 0;
}

}  // namespace vscan::raycast
