#include "app/core/checked_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "analysis/common/summary.h"
#include "app/core/fd_io.h"

namespace chatterlab::app {

namespace {

[[noreturn]] void throw_write_error(const std::filesystem::path& path, int e) {
  throw WriteError("cannot write " + path.string() + ": " +
                   (e != 0 ? std::strerror(e) : "the stream failed"));
}

}  // namespace

void write_file_checked(const std::filesystem::path& path, const std::string& text) {
  const auto fail = [&](int e) { throw_write_error(path, e); };  // e != 0 here
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0666);
  if (fd < 0) fail(errno);
  const auto write = [fd](const char* d, std::size_t k) {
    errno = 0;
    return ::write(fd, d, k);
  };
  if (!move_all(text.data(), text.size(), write)) {
    const int e = errno != 0 ? errno : EIO;  // a write that moved nothing: EIO
    ::close(fd);
    fail(e);
  }
  if (::close(fd) != 0) fail(errno);
}

std::ofstream open_for_writing(const std::filesystem::path& path) {
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw_write_error(path, errno);
  return out;
}

void close_checked(std::ofstream& out, const std::filesystem::path& path) {
  errno = 0;
  out.close();  // a stream failed earlier stays failed; the close retries what it still holds
  if (!out) throw_write_error(path, errno);
}

}  // namespace chatterlab::app
