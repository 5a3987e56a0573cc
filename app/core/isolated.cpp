#include "app/core/isolated.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <system_error>
#include <utility>

#include "analysis/common/summary.h"

namespace chatterlab::app {
namespace {

// The child's first reply byte: the work's bytes follow, or an error message.
constexpr char kOk = 'o';
constexpr char kInputError = 'i';
constexpr char kOtherError = 'x';

bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    data += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

}  // namespace

// The sanitizers' interface (sanitizer/common_interface_defs.h), weak: present only in a
// sanitizer build.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace {

// The work's outcome as a reply: a status byte, then the bytes or the error message.
std::string reply_of(const std::function<std::string()>& work) {
  try {
    return kOk + work();
  } catch (const InputError& e) {
    return kInputError + std::string(e.what());
  } catch (const std::exception& e) {
    return kOtherError + std::string(e.what());
  } catch (...) {
    return kOtherError + std::string("unknown exception");
  }
}

// The bytes of a reply (a status byte first, as reply_of writes it), or its error thrown as an
// InputError.
std::string from_reply(std::string reply, const IsolatedOptions& options) {
  const char kind = reply.empty() ? kOtherError : reply[0];
  if (!reply.empty()) reply.erase(0, 1);
  if (kind == kOk) return reply;
  if (kind == kInputError) throw InputError(reply);
  throw InputError(options.what + ": " + reply);
}

[[noreturn]] void child(int fd, const std::function<std::string()>& work) {
  // Under a sanitizer, a death callback the parent registered (libFuzzer's saves the current
  // input as a crash of the parent's) must not run when the child dies: the child's end is
  // reported to the parent, which goes on.
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  const std::string reply = reply_of(work);
  // _exit: no atexit handlers or static destructors of the parent's state run in the child.
  ::_exit(write_all(fd, reply.data(), reply.size()) ? 0 : 3);
}

[[noreturn]] void throw_too_long(const IsolatedOptions& options) {
  throw InputError(options.what + ": the reader process's reply passed " +
                   std::to_string(options.max_reply_bytes) +
                   " bytes; stopped (a damaged file declaring a huge array?)");
}

std::string signal_text(int sig) {
  const char* name = ::sigabbrev_np(sig);
  return "signal " + std::to_string(sig) + (name ? std::string(" (SIG") + name + ")" : "");
}

// Whether this process has threads besides the caller (Linux: /proc/self/task).
bool other_threads() {
  std::error_code ec;
  std::size_t n = 0;
  for (auto it = std::filesystem::directory_iterator("/proc/self/task", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
    if (++n > 1) return true;
  }
  return false;
}

// GCC 12's AddressSanitizer does not lock its allocator around fork (no fork interceptor in
// its libasan): a child forked while another thread holds an allocator lock waits for it
// forever. In a stress test (two threads allocating, the main thread forking children that
// allocate), 6 of 2,000 children hung. In that build (make sanitize) the work therefore runs in
// this process when other threads exist; the tests of the child process itself run
// single-threaded and still fork. glibc's allocator (every other build) is fork-safe.
#if defined(__SANITIZE_ADDRESS__) && !defined(__clang__)
constexpr bool kForkOnlySingleThreaded = true;
#else
constexpr bool kForkOnlySingleThreaded = false;
#endif

}  // namespace

std::string run_isolated(const std::function<std::string()>& work, const IsolatedOptions& options) {
  if (kForkOnlySingleThreaded && other_threads()) {
    std::string reply = reply_of(work);
    if (reply.size() > options.max_reply_bytes) throw_too_long(options);
    return from_reply(std::move(reply), options);
  }
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    throw InputError(options.what +
                     ": cannot start a reader process (pipe: " + std::strerror(errno) + ")");
  }
  std::fflush(nullptr);  // no buffered output written twice, by parent and child
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw InputError(options.what + ": cannot start a reader process (fork: " + std::strerror(err) +
                     ")");
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], work);
  }
  ::close(fds[1]);

  std::string reply;
  bool timed_out = false;
  bool too_long = false;  // the reply passed options.max_reply_bytes
  const auto deadline = std::chrono::steady_clock::now() + options.time_limit;
  char block[65536];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1 << 30)));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) break;
    if (r == 0) continue;  // the deadline is checked above
    const ssize_t n = ::read(fds[0], block, sizeof block);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of the reply (or a read error: judged by the exit status)
    if (static_cast<std::size_t>(n) > options.max_reply_bytes - reply.size()) {
      too_long = true;
      break;
    }
    reply.append(block, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (timed_out || too_long) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }

  if (too_long) throw_too_long(options);
  if (timed_out) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", static_cast<double>(options.time_limit.count()) / 1e3);
    throw InputError(options.what + ": not finished after " + limit +
                     " s; stopped (a damaged file?)");
  }
  if (WIFSIGNALED(status)) {
    throw InputError(options.what + ": the reader process was ended by " +
                     signal_text(WTERMSIG(status)) + " (a damaged file the library cannot read)");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || reply.empty()) {
    throw InputError(options.what + ": the reader process failed (exit status " +
                     std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                     ", a damaged file the library cannot read)");
  }
  return from_reply(std::move(reply), options);
}

void ByteWriter::u64(std::uint64_t v) {
  bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
}

void ByteWriter::f64(const double* values, std::size_t n) {
  bytes_.append(reinterpret_cast<const char*>(values), n * sizeof(double));
}

void ByteWriter::str(const std::string& s) {
  u64(s.size());
  bytes_.append(s);
}

void ByteReader::need(std::size_t n) const {
  if (n > bytes_.size() - pos_) throw InputError(what_ + ": the reader process's reply is short");
}

std::uint64_t ByteReader::u64() {
  need(sizeof(std::uint64_t));
  std::uint64_t v = 0;
  std::memcpy(&v, bytes_.data() + pos_, sizeof v);
  pos_ += sizeof v;
  return v;
}

void ByteReader::f64(double* out, std::size_t n) {
  if (n > (bytes_.size() - pos_) / sizeof(double)) need(bytes_.size() - pos_ + 1);
  std::memcpy(out, bytes_.data() + pos_, n * sizeof(double));
  pos_ += n * sizeof(double);
}

std::string ByteReader::str() {
  const std::uint64_t n = u64();
  need(n);
  std::string s = bytes_.substr(pos_, n);
  pos_ += n;
  return s;
}

}  // namespace chatterlab::app
