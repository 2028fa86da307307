// Interning: which of n keys are equal, so that equal values are stored once and each owner keeps
// an index. Sort-based rather than a map: its scratch is two flat arrays, which a large world's
// allocator hands back to the system when they are freed (a map of 10^6 nodes would stay resident
// in the heap after compiling a world whose bodies are all different).
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace rigid::physics::detail {

// index[i]: the rank of keys[i] among the distinct keys, numbered in order of first appearance;
// first[k]: the position of the first key of rank k. Keys need operator< and operator==.
template <class Key>
void intern(const std::vector<Key>& keys, std::vector<std::int32_t>& index,
            std::vector<std::int32_t>& first) {
  const auto n = static_cast<std::int32_t>(keys.size());
  std::vector<std::int32_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  // Stable: within a run of equal keys the first appearance comes first.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::int32_t a, std::int32_t b) { return keys[a] < keys[b]; });
  index.assign(keys.size(), 0);
  first.clear();
  // Each run's first position, then the runs renumbered in order of those positions.
  std::vector<std::int32_t> run_of(keys.size());
  for (std::int32_t k = 0; k < n; ++k) {
    if (k == 0 || !(keys[order[k]] == keys[order[k - 1]])) first.push_back(order[k]);
    run_of[order[k]] = static_cast<std::int32_t>(first.size()) - 1;
  }
  std::vector<std::int32_t> rank(first.size());
  std::iota(rank.begin(), rank.end(), 0);
  std::sort(rank.begin(), rank.end(),
            [&](std::int32_t a, std::int32_t b) { return first[a] < first[b]; });
  std::vector<std::int32_t> renumber(first.size());
  for (std::size_t r = 0; r < rank.size(); ++r)
    renumber[rank[r]] = static_cast<std::int32_t>(r);
  std::vector<std::int32_t> sorted_first(first.size());
  for (std::size_t r = 0; r < rank.size(); ++r)
    sorted_first[r] = first[rank[r]];
  first.swap(sorted_first);
  for (std::int32_t i = 0; i < n; ++i)
    index[i] = renumber[run_of[i]];
}

}  // namespace rigid::physics::detail
