#include "api/scan/chunk_packer.h"

#include <algorithm>
#include <string>

#include "vscan/common/point_cloud.h"

namespace vscan::api {
namespace {

template <typename T>
void Append(const T* values, size_t first, size_t n, size_t per_point, std::string* out) {
  out->append(reinterpret_cast<const char*>(values + first * per_point), n * per_point * sizeof(T));
}

}  // namespace

ChunkPacker::ChunkPacker(uint32_t fields, size_t points_per_chunk, ScanOutbox& outbox)
    : fields_(fields), points_per_chunk_(std::max<size_t>(1, points_per_chunk)), outbox_(outbox) {}

void ChunkPacker::Accept(const raycast::RowBlock& block) {
  for (uint32_t r = 0; r < block.rows; ++r) {
    uint32_t done = 0;
    while (done < block.count[r]) {
      if (!open_) Open();
      const auto n = static_cast<uint32_t>(std::min<size_t>(block.count[r] - done, points_per_chunk_ - in_open_));
      CopyRow(block, r, done, n);
      done += n;
      in_open_ += n;
      if (in_open_ == points_per_chunk_) Ship();
    }
  }
}

void ChunkPacker::Flush() {
  if (open_) Ship();
}

void ChunkPacker::CopyRow(const raycast::RowBlock& block, uint32_t r, uint32_t begin, uint32_t n) {
  v1::PointChunk* chunk = open_->mutable_chunk();
  const size_t first = size_t{r} * block.stride + begin;
  Append(block.positions, first, n, 3, chunk->mutable_positions());
  if (fields_ & kFieldNormal) Append(block.normals, first, n, 3, chunk->mutable_normals());
  if (fields_ & kFieldRange) Append(block.ranges, first, n, 1, chunk->mutable_ranges());
  if (fields_ & kFieldIntensity) Append(block.intensities, first, n, 1, chunk->mutable_intensities());
  if (fields_ & kFieldInstanceId) Append(block.instance_ids, first, n, 1, chunk->mutable_instance_ids());
  if (fields_ & kFieldPixel) Append(block.pixels, first, n, 1, chunk->mutable_pixels());
}

// Each array is reserved whole, so appending rows never reallocates.
void ChunkPacker::Open() {
  open_ = std::make_unique<v1::ScanResponse>();
  v1::PointChunk* chunk = open_->mutable_chunk();
  const size_t n = points_per_chunk_;
  chunk->mutable_positions()->reserve(12 * n);
  if (fields_ & kFieldNormal) chunk->mutable_normals()->reserve(12 * n);
  if (fields_ & kFieldRange) chunk->mutable_ranges()->reserve(4 * n);
  if (fields_ & kFieldIntensity) chunk->mutable_intensities()->reserve(4 * n);
  if (fields_ & kFieldInstanceId) chunk->mutable_instance_ids()->reserve(4 * n);
  if (fields_ & kFieldPixel) chunk->mutable_pixels()->reserve(4 * n);
  in_open_ = 0;
}

void ChunkPacker::Ship() {
  v1::PointChunk* chunk = open_->mutable_chunk();
  chunk->set_index(chunks_++);
  chunk->set_count(static_cast<uint32_t>(in_open_));
  points_ += in_open_;
  outbox_.Push(std::move(open_));
  in_open_ = 0;
}

}  // namespace vscan::api
