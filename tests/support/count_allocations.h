// Heap allocations counted while chatterlab::testing::g_counting is set, for tests that a step
// loop allocates nothing. malloc is interposed (glibc's own is __libc_malloc): it sees operator
// new and Eigen's allocations alike. Not under AddressSanitizer, which interposes malloc
// itself: kCountingMalloc is false there and the tests skip.
//
// Defines malloc: include it in one translation unit of a test executable only (every
// tests/**/*_test.cpp is its own executable).
#pragma once

#include <cstddef>

namespace chatterlab::testing {
inline bool g_counting = false;
inline long g_allocations = 0;
}  // namespace chatterlab::testing

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kCountingMalloc = false;
#else
constexpr bool kCountingMalloc = true;
extern "C" void* __libc_malloc(std::size_t n);
extern "C" void* malloc(std::size_t n) {
  if (chatterlab::testing::g_counting) ++chatterlab::testing::g_allocations;
  return __libc_malloc(n);
}
#endif
