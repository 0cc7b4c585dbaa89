// Sorting networks: a fixed sequence of compare-exchanges that sorts any input
// of its size. Each one is a pair of selects, not a branch, so sorting a few
// keys in an order the branch predictor cannot follow costs no mispredictions
// (an insertion sort, which std::sort uses on small ranges, mispredicts about
// once per key).
#pragma once

#include <array>
#include <cstddef>
#include <utility>

namespace mbao {
namespace sorting_network {

struct Comparator {
  std::size_t lo = 0, hi = 0;
};

// Batcher's odd-even merge sort on N = 2^k keys: each pass merges sorted runs
// of p keys into runs of 2p. Called with nullptr it only counts.
constexpr std::size_t batcher_comparators(std::size_t n, Comparator* out) {
  std::size_t count = 0;
  for (std::size_t p = 1; p < n; p <<= 1)
    for (std::size_t k = p; k >= 1; k >>= 1)
      for (std::size_t j = k % p; j + k < n; j += 2 * k)
        for (std::size_t i = 0; i < k && i + j + k < n; ++i)
          if ((i + j) / (2 * p) == (i + j + k) / (2 * p)) {
            if (out) out[count] = {i + j, i + j + k};
            ++count;
          }
  return count;
}

template <std::size_t N>
constexpr std::array<Comparator, batcher_comparators(N, nullptr)> batcher_network() {
  std::array<Comparator, batcher_comparators(N, nullptr)> network{};
  batcher_comparators(N, network.data());
  return network;
}

// On scalar keys, written so that GCC makes it a compare and two conditional
// moves: with std::min and std::max, or selects between structs, it branched.
template <class Key>
void compare_exchange(Key& a, Key& b) {
  const Key x = a, y = b;
  const bool in_order = x < y;
  a = in_order ? x : y;
  b = in_order ? y : x;
}

template <class Key, std::size_t N, std::size_t... I>
void apply(Key (&keys)[N], std::index_sequence<I...>) {
  constexpr auto network = batcher_network<N>();
  (compare_exchange(keys[network[I].lo], keys[network[I].hi]), ...);
}

}  // namespace sorting_network

// Sorts N = 2^k scalar keys with Batcher's network, unrolled at compile time so
// that the keys can live in registers.
template <class Key, std::size_t N>
void network_sort(Key (&keys)[N]) {
  sorting_network::apply(keys, std::make_index_sequence<sorting_network::batcher_comparators(N, nullptr)>());
}

}  // namespace mbao
