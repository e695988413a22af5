#include "store/ids.h"

#include <unistd.h>

#include <chrono>
#include <random>

namespace vscan::store {

std::string NewId(std::string_view prefix) {
  thread_local std::mt19937_64 rng;
  thread_local pid_t seeded_in = 0;
  // Reseed after a fork too, or parent and child would hand out the same ids.
  if (seeded_in != ::getpid()) {
    std::random_device device;
    std::seed_seq seed{device(), device(), device(), device(), device(), device(), device(), device()};
    rng.seed(seed);
    seeded_in = ::getpid();
  }
  static constexpr char kHex[] = "0123456789abcdef";
  const uint64_t bits = rng();
  std::string id(prefix);
  for (int shift = 60; shift >= 0; shift -= 4) id.push_back(kHex[(bits >> shift) & 0xf]);
  return id;
}

int64_t NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace vscan::store
