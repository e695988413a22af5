#pragma once
// The 16 lanes of one 4x4 packet: aiming the rays and turning Embree's hits into point fields.
// Loops run over the lanes of one field at a time so that they vectorise.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <embree3/rtcore.h>

#include "raycast/scan_setup.h"

namespace vscan::raycast {

enum FloatLane : uint32_t { kPosX, kPosY, kPosZ, kNormalX, kNormalY, kNormalZ, kRange, kIntensity, kFloatLanes };
enum UintLane : uint32_t { kInstance, kPixel, kUintLanes };

// Per-lane values of one packet, field by field, so the loops over lanes vectorise.
struct alignas(64) Lanes {
  float sy[kPacketLanes];  // sensor-frame y of the rays (z = 1)
  float floats[kFloatLanes][kPacketLanes];
  uint32_t uints[kUintLanes][kPacketLanes];
  uint32_t hit[kPacketLanes];
};

[[gnu::always_inline]] inline void InitStripRays(const ScanSetup& setup, RTCRayHit16& packet) {
  for (uint32_t i = 0; i < kPacketLanes; ++i) {
    packet.ray.org_x[i] = setup.origin.x();
    packet.ray.org_y[i] = setup.origin.y();
    packet.ray.org_z[i] = setup.origin.z();
    packet.ray.tnear[i] = setup.near;
    packet.ray.time[i] = 0.0f;
    packet.ray.mask[i] = 0xFFFFFFFFu;
    packet.ray.id[i] = i;
    packet.ray.flags[i] = 0;
  }
}

// Sets the packet's directions from sx and lanes.sy and resets what Embree overwrites.
[[gnu::always_inline]] inline void AimPacket(const ScanSetup& setup, const float* __restrict sx, const Lanes& lanes,
                                             RTCRayHit16& __restrict packet) {
  for (uint32_t i = 0; i < kPacketLanes; ++i) {
    setup.WorldDirection(sx[i], lanes.sy[i], packet.ray.dir_x[i], packet.ray.dir_y[i], packet.ray.dir_z[i]);
    packet.ray.tfar[i] = setup.far;
    packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
  }
}

// Computes the lanes' positions and ranges, and normals and intensities when asked for; lanes
// that missed produce values nobody reads.
[[gnu::always_inline]] inline void ComputeFloatLanes(const ScanSetup& setup, const float* __restrict sx,
                                                     const RTCRayHit16& __restrict packet, Lanes& __restrict lanes) {
  const RTCRay16& ray = packet.ray;
  const RTCHit16& hit = packet.hit;
  const Eigen::Matrix3f& r = setup.world_from_sensor_rotation;
  float dir_len[kPacketLanes];
  for (uint32_t i = 0; i < kPacketLanes; ++i) {
    const float t = ray.tfar[i];
    dir_len[i] = std::sqrt(sx[i] * sx[i] + lanes.sy[i] * lanes.sy[i] + 1.0f);
    lanes.floats[kRange][i] = t * dir_len[i];
    if (setup.sensor_frame) {
      lanes.floats[kPosX][i] = t * sx[i];
      lanes.floats[kPosY][i] = t * lanes.sy[i];
      lanes.floats[kPosZ][i] = t;
    } else {
      lanes.floats[kPosX][i] = ray.org_x[i] + t * ray.dir_x[i];
      lanes.floats[kPosY][i] = ray.org_y[i] + t * ray.dir_y[i];
      lanes.floats[kPosZ][i] = ray.org_z[i] + t * ray.dir_z[i];
    }
  }
  if ((setup.fields & (kFieldNormal | kFieldIntensity)) == 0) return;

  const float power = setup.power, constant = setup.constant, linear = setup.linear, quadratic = setup.quadratic;
  float nx[kPacketLanes], ny[kPacketLanes], nz[kPacketLanes];
  for (uint32_t i = 0; i < kPacketLanes; ++i) {
    const float ngx = hit.Ng_x[i], ngy = hit.Ng_y[i], ngz = hit.Ng_z[i];
    const float inv_ng = 1.0f / std::sqrt(ngx * ngx + ngy * ngy + ngz * ngz);
    const float facing = ngx * ray.dir_x[i] + ngy * ray.dir_y[i] + ngz * ray.dir_z[i];
    // Unit normal turned towards the sensor.
    const float scale = std::copysign(inv_ng, -facing);
    nx[i] = ngx * scale;
    ny[i] = ngy * scale;
    nz[i] = ngz * scale;
    // power * cos(incidence) / attenuation, with cos = |facing| / (|Ng| |dir|) and one division.
    const float range = lanes.floats[kRange][i];
    const float attenuation = constant + (linear + quadratic * range) * range;
    lanes.floats[kIntensity][i] = power * std::abs(facing) * inv_ng / (dir_len[i] * attenuation);
  }
  if (setup.sensor_frame) {
    const float r00 = r(0, 0), r01 = r(0, 1), r02 = r(0, 2), r10 = r(1, 0), r11 = r(1, 1), r12 = r(1, 2);
    const float r20 = r(2, 0), r21 = r(2, 1), r22 = r(2, 2);
    for (uint32_t i = 0; i < kPacketLanes; ++i) {
      lanes.floats[kNormalX][i] = r00 * nx[i] + r10 * ny[i] + r20 * nz[i];
      lanes.floats[kNormalY][i] = r01 * nx[i] + r11 * ny[i] + r21 * nz[i];
      lanes.floats[kNormalZ][i] = r02 * nx[i] + r12 * ny[i] + r22 * nz[i];
    }
  } else {
    std::memcpy(lanes.floats[kNormalX], nx, sizeof(nx));
    std::memcpy(lanes.floats[kNormalY], ny, sizeof(ny));
    std::memcpy(lanes.floats[kNormalZ], nz, sizeof(nz));
  }
}

[[gnu::always_inline]] inline void ComputeUintLanes(const ScanSetup& setup, const RTCRayHit16& packet,
                                                    uint32_t first_pixel, Lanes& lanes) {
  if (setup.fields & kFieldInstanceId) {
    const uint32_t* table = setup.instance_of_geometry.data();
    const auto last = static_cast<uint32_t>(setup.instance_of_geometry.size() - 1);
    for (uint32_t i = 0; i < kPacketLanes; ++i) {
      lanes.uints[kInstance][i] = table[static_cast<int32_t>(std::min(packet.hit.geomID[i], last))];
    }
  }
  if (setup.fields & kFieldPixel) {
#pragma GCC unroll 1
    for (uint32_t i = 0; i < kPacketLanes; ++i) {
      lanes.uints[kPixel][i] = first_pixel + (i / kPacketSide) * setup.width + i % kPacketSide;
    }
  }
}

}  // namespace vscan::raycast
