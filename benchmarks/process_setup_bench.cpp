// Process setup shared by every benchmark: the heap policy of the chatterlab program
// (app/core/allocator.h), applied before main so that benchmarks measure what the program runs.
// (The file holds no benchmark; the name matches the folder's *_bench.cpp glob.)
#include "app/core/allocator.h"

namespace {

const bool kAllocatorConfigured = [] {
  chatterlab::app::configure_allocator();
  return true;
}();

}  // namespace
