#pragma once
// Hands blocks of image rows to `threads` threads (the calling one among them) until none are left:
// how the independent renderers of fieldcast_bench_table use the cores.

#include <atomic>
#include <thread>
#include <vector>

namespace fieldcast::core {

/// Calls fn(first, end) for blocks of `block` rows of [0, rows) on `threads` threads.
template <class Fn>
void shareRows(int rows, int block, int threads, const Fn& fn) {
  std::atomic<int> next{0};
  const auto work = [&] {
    for (int first = next.fetch_add(block); first < rows; first = next.fetch_add(block)) {
      fn(first, first + block < rows ? first + block : rows);
    }
  };
  std::vector<std::jthread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
}

}  // namespace fieldcast::core
