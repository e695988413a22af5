#include "raycast/strip_tracer.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <limits>
#include <new>

#include <tbb/scalable_allocator.h>

#include "raycast/packet_lanes.h"

namespace vscan::raycast {
namespace {

// Appends the hits among four lanes of x, y, z as 3-vectors. With misses, each lane is written
// at the next free slot, which only a hit claims: no branch per lane. Rows are padded to whole
// packets, so the slot stays inside the row.
[[gnu::always_inline]] inline void StoreVectors(const float* x, const float* y, const float* z,
                                                const uint32_t* hit, uint32_t hits, float* out) {
  if (hits == kPacketSide) {
    for (uint32_t j = 0; j < kPacketSide; ++j) {
      out[3 * j] = x[j];
      out[3 * j + 1] = y[j];
      out[3 * j + 2] = z[j];
    }
    return;
  }
  uint32_t k = 0;
  for (uint32_t j = 0; j < kPacketSide; ++j) {
    out[3 * k] = x[j];
    out[3 * k + 1] = y[j];
    out[3 * k + 2] = z[j];
    k += hit[j];
  }
}

template <typename T>
[[gnu::always_inline]] inline void StoreValues(const T* lanes, const uint32_t* hit, uint32_t hits, T* out) {
  if (hits == kPacketSide) {
    std::memcpy(out, lanes, sizeof(T) * kPacketSide);
    return;
  }
  uint32_t k = 0;
  for (uint32_t j = 0; j < kPacketSide; ++j) {
    out[k] = lanes[j];
    k += hit[j];
  }
}

// Appends the hits of packet row `row` to the strip's arrays.
[[gnu::always_inline]] inline void StoreRow(uint32_t fields, const Lanes& lanes, uint32_t row, StripHits& out) {
  const uint32_t first = row * kPacketSide;
  const uint32_t* hit = lanes.hit + first;
  const uint32_t hits = hit[0] + hit[1] + hit[2] + hit[3];
  if (hits == 0) return;
  const size_t at = size_t{row} * out.stride + out.count[row];
  const auto lane = [&](uint32_t f) { return lanes.floats[f] + first; };
  StoreVectors(lane(kPosX), lane(kPosY), lane(kPosZ), hit, hits, out.positions + 3 * at);
  if (fields & kFieldNormal) StoreVectors(lane(kNormalX), lane(kNormalY), lane(kNormalZ), hit, hits, out.normals + 3 * at);
  if (fields & kFieldRange) StoreValues(lane(kRange), hit, hits, out.ranges + at);
  if (fields & kFieldIntensity) StoreValues(lane(kIntensity), hit, hits, out.intensities + at);
  if (fields & kFieldInstanceId) StoreValues(lanes.uints[kInstance] + first, hit, hits, out.instance_ids + at);
  if (fields & kFieldPixel) StoreValues(lanes.uints[kPixel] + first, hit, hits, out.pixels + at);
  out.count[row] += hits;
}

}  // namespace

StripHits::StripHits(uint32_t row_stride) : stride(row_stride) {
  const size_t slots = size_t{kPacketSide} * stride;
  // Arrays whose starts are a multiple of 4 KiB apart compete for the same L1 sets; an extra
  // 64 bytes per array spreads them. tbbmalloc recycles the block across scans (no page faults).
  const size_t sizes[] = {3 * slots, 3 * slots, slots, slots, slots, slots};
  size_t offsets[6], bytes = 0;
  for (int i = 0; i < 6; ++i) {
    offsets[i] = bytes;
    bytes += sizes[i] * sizeof(float) + 64;
  }
  block_.reset(scalable_aligned_malloc(bytes, 64));
  if (block_ == nullptr) throw std::bad_alloc();
  std::byte* base = static_cast<std::byte*>(block_.get());
  positions = reinterpret_cast<float*>(base + offsets[0]);
  normals = reinterpret_cast<float*>(base + offsets[1]);
  ranges = reinterpret_cast<float*>(base + offsets[2]);
  intensities = reinterpret_cast<float*>(base + offsets[3]);
  instance_ids = reinterpret_cast<uint32_t*>(base + offsets[4]);
  pixels = reinterpret_cast<uint32_t*>(base + offsets[5]);
}

RowBlock StripHits::Block() const {
  return RowBlock{first_row, rows, stride, count, positions, normals, ranges, intensities, instance_ids, pixels};
}

void StripHits::Free::operator()(void* p) const { scalable_aligned_free(p); }

// Built for three instruction sets; the loader picks the best the CPU runs.
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
void TraceStrip(const ScanSetup& setup, uint32_t strip, StripHits& hits) {
  const uint32_t v0 = strip * kPacketSide;
  const uint32_t rows = std::min(kPacketSide, setup.height - v0);
  hits.count = {};
  hits.first_row = v0;
  hits.rows = rows;
  int32_t min_bits = std::bit_cast<int32_t>(std::numeric_limits<float>::infinity());
  int32_t max_bits = 0;

  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  RTCRayHit16 packet;
  InitStripRays(setup, packet);
  Lanes lanes;
  for (uint32_t i = 0; i < kPacketLanes; ++i) lanes.sy[i] = setup.row_y[v0 + i / kPacketSide];
  // Lanes past the image: rows below it in the last strip, columns right of it in the last packet.
  const uint32_t last_columns = setup.width - (setup.padded_width - kPacketSide);
  alignas(64) int valid[kPacketLanes], last_valid[kPacketLanes];
  for (uint32_t i = 0; i < kPacketLanes; ++i) {
    valid[i] = i / kPacketSide < rows ? -1 : 0;
    last_valid[i] = i % kPacketSide < last_columns ? valid[i] : 0;
  }

  for (uint32_t u0 = 0; u0 < setup.width; u0 += kPacketSide) {
    const float* sx = setup.packet_x.data() + size_t{kPacketSide} * u0;
    AimPacket(setup, sx, lanes, packet);
    rtcIntersect16(u0 + kPacketSide < setup.padded_width ? valid : last_valid, setup.scene, &context, &packet);

    // Kept as loops (not unrolled into scalar code), so they vectorise.
#pragma GCC unroll 1
    for (uint32_t i = 0; i < kPacketLanes; ++i) lanes.hit[i] = packet.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    uint32_t packet_hits = 0;
#pragma GCC unroll 1
    for (uint32_t i = 0; i < kPacketLanes; ++i) packet_hits += lanes.hit[i];
    if (packet_hits == 0) continue;
    ComputeFloatLanes(setup, sx, packet, lanes);
    ComputeUintLanes(setup, packet, v0 * setup.width + u0, lanes);
    // Ranges are positive, so their bit patterns order like the values and this vectorises.
#pragma GCC unroll 1
    for (uint32_t i = 0; i < kPacketLanes; ++i) {
      const int32_t bits = std::bit_cast<int32_t>(lanes.floats[kRange][i]);
      min_bits = std::min(min_bits, lanes.hit[i] != 0 ? bits : std::numeric_limits<int32_t>::max());
      max_bits = std::max(max_bits, lanes.hit[i] != 0 ? bits : 0);
    }
    for (uint32_t row = 0; row < rows; ++row) StoreRow(setup.fields, lanes, row, hits);
  }
  hits.min_range = std::bit_cast<float>(min_bits);
  hits.max_range = std::bit_cast<float>(max_bits);
}

}  // namespace vscan::raycast
