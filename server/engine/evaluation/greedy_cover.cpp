#include "evaluation/greedy_cover.h"

#include <algorithm>
#include <bit>

namespace vscan::evaluation {

size_t SampleBits::Count() const {
  size_t n = 0;
  for (const uint64_t w : words_) n += static_cast<size_t>(std::popcount(w));
  return n;
}

size_t SampleBits::CountNotIn(const SampleBits& other) const {
  size_t n = 0;
  for (size_t i = 0; i < words_.size(); ++i) n += static_cast<size_t>(std::popcount(words_[i] & ~other.words_[i]));
  return n;
}

void SampleBits::Add(const SampleBits& other) {
  for (size_t i = 0; i < words_.size(); ++i) words_[i] |= other.words_[i];
}

std::vector<CoverPick> GreedyMaxCoverage(std::span<const SampleBits> sets, size_t universe, size_t max_picks,
                                         size_t min_gain) {
  min_gain = std::max<size_t>(min_gain, 1);
  SampleBits covered(universe);
  std::vector<CoverPick> picks;
  while (picks.size() < max_picks) {
    CoverPick best;
    for (size_t i = 0; i < sets.size(); ++i) {
      const size_t gain = sets[i].CountNotIn(covered);
      if (gain > best.gain) best = {i, gain};
    }
    if (best.gain < min_gain) break;
    covered.Add(sets[best.set]);
    picks.push_back(best);
  }
  return picks;
}

}  // namespace vscan::evaluation
