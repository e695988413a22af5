#include "raycast/stream_copy.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include <immintrin.h>

namespace vscan::raycast {
namespace {

constexpr size_t kLine = 64;

// Bytes from p to the next cache-line boundary.
size_t ToLineBoundary(const void* p) { return (kLine - reinterpret_cast<uintptr_t>(p) % kLine) % kLine; }

__attribute__((target("avx512f"))) void StreamCopyAvx512(char* d, const char* s, size_t bytes) {
  const size_t head = std::min(bytes, ToLineBoundary(d));
  std::memcpy(d, s, head);
  d += head;
  s += head;
  bytes -= head;
  for (; bytes >= kLine; bytes -= kLine, d += kLine, s += kLine) {
    _mm512_stream_si512(reinterpret_cast<__m512i*>(d), _mm512_loadu_si512(s));
  }
  std::memcpy(d, s, bytes);
}

__attribute__((target("avx"))) void StreamCopyAvx(char* d, const char* s, size_t bytes) {
  const size_t head = std::min(bytes, ToLineBoundary(d));
  std::memcpy(d, s, head);
  d += head;
  s += head;
  bytes -= head;
  for (; bytes >= kLine; bytes -= kLine, d += kLine, s += kLine) {
    _mm256_stream_si256(reinterpret_cast<__m256i*>(d), _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s)));
    _mm256_stream_si256(reinterpret_cast<__m256i*>(d + 32),
                        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s + 32)));
  }
  std::memcpy(d, s, bytes);
}

void PlainCopy(char* d, const char* s, size_t bytes) { std::memcpy(d, s, bytes); }

using CopyFunction = void (*)(char*, const char*, size_t);

CopyFunction PickCopy() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return StreamCopyAvx512;
  if (__builtin_cpu_supports("avx")) return StreamCopyAvx;
  return PlainCopy;
}

}  // namespace

void StreamCopy(void* dst, const void* src, size_t bytes) {
  static const CopyFunction copy = PickCopy();
  copy(static_cast<char*>(dst), static_cast<const char*>(src), bytes);
}

void StreamFence() { _mm_sfence(); }

}  // namespace vscan::raycast
