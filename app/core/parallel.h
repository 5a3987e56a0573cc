// Runs fn(i) for i in [0, n) on up to `jobs` threads (0: one per hardware thread). An exception
// thrown by fn stops the remaining work and is rethrown to the caller once every thread has
// stopped (the first one thrown, when several threads throw).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace chatterlab::app {

template <typename Fn>
void parallel_for(std::size_t n, int jobs, Fn&& fn) {
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = std::clamp(jobs > 0 ? jobs : hw, 1, std::max(1, static_cast<int>(n)));
  std::atomic<std::size_t> next{0};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        next = n;  // no further items start
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 1; j < threads; ++j) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace chatterlab::app
