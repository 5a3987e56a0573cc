#include "app/core/allocator.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace chatterlab::app {

void configure_allocator() {
#if defined(__GLIBC__)
  constexpr int kMiB = 1 << 20;
  mallopt(M_MMAP_THRESHOLD, 256 * kMiB);
  mallopt(M_TRIM_THRESHOLD, 512 * kMiB);
  mallopt(M_TOP_PAD, 64 * kMiB);
#endif
}

}  // namespace chatterlab::app
