#pragma once
// Greedy maximum coverage over sets of sample indices held as bitsets.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vscan::evaluation {

// A set of indices in [0, size()).
class SampleBits {
 public:
  explicit SampleBits(size_t size = 0) : size_(size), words_((size + 63) / 64, 0) {}

  size_t size() const { return size_; }
  void Set(size_t i) { words_[i / 64] |= uint64_t{1} << (i % 64); }
  bool Test(size_t i) const { return (words_[i / 64] >> (i % 64)) & 1; }
  size_t Count() const;
  // Members of this set that are not in other (of the same size).
  size_t CountNotIn(const SampleBits& other) const;
  // Adds other's members (of the same size).
  void Add(const SampleBits& other);

 private:
  size_t size_;
  std::vector<uint64_t> words_;
};

struct CoverPick {
  size_t set = 0;   // index into the sets
  size_t gain = 0;  // members it adds to those of the sets picked before it
};

// Repeatedly picks the set that adds most members not yet covered (the lowest index on a tie),
// until max_picks are made or the best gain is below min_gain (at least 1). All sets have size
// universe.
std::vector<CoverPick> GreedyMaxCoverage(std::span<const SampleBits> sets, size_t universe, size_t max_picks,
                                         size_t min_gain);

}  // namespace vscan::evaluation
