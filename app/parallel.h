// Runs fn(i) for i in [0, n) on up to `jobs` threads (0: one per hardware thread).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace chatterlab::app {

template <typename Fn>
void parallel_for(std::size_t n, int jobs, Fn&& fn) {
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = std::clamp(jobs > 0 ? jobs : hw, 1, std::max(1, static_cast<int>(n)));
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < n; i = next++) fn(i);
  };
  std::vector<std::thread> pool;
  for (int j = 1; j < threads; ++j) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
}

}  // namespace chatterlab::app
