#pragma once
// Moving bytes through a file descriptor whose calls may each move part of them.
#include <sys/types.h>

#include <cerrno>
#include <cstddef>

namespace chatterlab::app {

// Moves all n bytes at data with io(data, left) (a ::read, ::write or ::send), one call after
// another: a call moves part of them, EINTR retries. False when a call fails (errno says why)
// or returns 0 (the other end closed the stream, or a write that moved nothing; errno is then
// left as it was).
template <typename Byte, typename Io>
bool move_all(Byte* data, std::size_t n, Io io) {
  while (n > 0) {
    const ssize_t moved = io(data, n);
    if (moved < 0 && errno == EINTR) continue;
    if (moved <= 0) return false;
    data += moved;
    n -= static_cast<std::size_t>(moved);
  }
  return true;
}

}  // namespace chatterlab::app
