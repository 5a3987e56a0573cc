// A kind's save() and restore() for the per-test cache (app/pipeline/kind.h), when its result
// is one struct T with a fields() list (app/core/archive.h): the bytes of the result, and the
// result read back from them.
#pragma once

#include <memory>
#include <string>

#include "app/core/archive.h"
#include "app/pipeline/outcome.h"

namespace chatterlab::app {

template <class T>
std::string save_result(const Outcome& out) {
  return to_bytes(out.result_of<T>());
}

// @throws InputError on damaged bytes (out is left as it was)
template <class T>
void restore_result(const std::string& bytes, Outcome& out) {
  auto r = std::make_unique<T>();
  from_bytes(bytes, *r);
  out.result = std::move(r);
}

}  // namespace chatterlab::app
