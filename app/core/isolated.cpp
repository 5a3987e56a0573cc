#include "app/core/isolated.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
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
#include "app/core/fd_io.h"

namespace chatterlab::app {
namespace {

// The child's first reply byte: the work's bytes follow, or an error message.
constexpr char kOk = 'o';
constexpr char kInputError = 'i';
constexpr char kOtherError = 'x';

bool write_all(int fd, const char* data, std::size_t n) {
  return move_all(data, n, [fd](const char* d, std::size_t k) { return ::write(fd, d, k); });
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

// In a reader process (forked, not exec'd, so it has the parent's handlers): a crash ends it at
// once, by its signal, which the parent names, on both paths alike. Without this, a handler of
// the parent's would run in the child: libFuzzer's (SIGSEGV, SIGABRT, SIGINT, ...) would save
// the parent's current input as a crash of the target, which is not where the crash was (and in
// a kept process the input of up to 999 reads before), and exit with its own status; a
// sanitizer's would print a report of what is a contained failure (a symbolized one starts a
// symbolizer process). In the .mat fuzz target 237 of 268 reader deaths in a 30 s run were SEGVs
// inside libhdf5. A heap error the sanitizer finds is still reported, and exits with its status.
void reader_process_signals() {
  // A death callback the parent registered (libFuzzer's saves the current input) must not run.
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM, SIGXFSZ, SIGUSR1,
                        SIGUSR2, SIGALRM}) {
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    ::sigaction(sig, &dfl, nullptr);
  }
}

[[noreturn]] void child(int fd, const std::function<std::string()>& work) {
  reader_process_signals();
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

namespace {

// How reading a reply from a child ended.
enum class Got { kAll, kEnd, kTimedOut, kTooLong };

// Appends what the child sends on `fd` to `out` until `out` holds `want` bytes (kAll; with
// `want` = npos only the end of the stream ends it), the stream ends (kEnd), the deadline passes
// (kTimedOut), or `out` would pass `max` bytes (kTooLong).
Got receive(int fd, std::string& out, std::size_t want, std::size_t max,
            std::chrono::steady_clock::time_point deadline) {
  char block[65536];
  while (out.size() < want) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return Got::kTimedOut;
    pollfd p{fd, POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1 << 30)));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return Got::kEnd;
    if (r == 0) continue;  // the deadline is checked above
    const std::size_t ask = std::min(sizeof block, want - out.size());
    const ssize_t n = ::read(fd, block, ask);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return Got::kEnd;  // end of the stream (or a read error: judged by the exit status)
    if (static_cast<std::size_t>(n) > max - out.size()) return Got::kTooLong;
    out.append(block, static_cast<std::size_t>(n));
  }
  return Got::kAll;
}

[[noreturn]] void throw_timed_out(const IsolatedOptions& options) {
  char limit[32];
  std::snprintf(limit, sizeof limit, "%g", static_cast<double>(options.time_limit.count()) / 1e3);
  throw InputError(options.what + ": not finished after " + limit +
                   " s; stopped (a damaged file?)");
}

// The InputError for a child that ended (waitpid's `status`) without a whole reply.
[[noreturn]] void throw_ended(int status, const IsolatedOptions& options) {
  if (WIFSIGNALED(status)) {
    throw InputError(options.what + ": the reader process was ended by " +
                     signal_text(WTERMSIG(status)) + " (a damaged file the library cannot read)");
  }
  throw InputError(options.what + ": the reader process failed (exit status " +
                   std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                   ", a damaged file the library cannot read)");
}

int wait_for(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

// The work in this process (GCC's ASan build with other threads: see kForkOnlySingleThreaded).
std::string in_this_process(const std::function<std::string()>& work,
                            const IsolatedOptions& options) {
  std::string reply = reply_of(work);
  if (reply.size() > options.max_reply_bytes) throw_too_long(options);
  return from_reply(std::move(reply), options);
}

[[noreturn]] void throw_cannot_start(const IsolatedOptions& options, const char* call, int err) {
  throw InputError(options.what + ": cannot start a reader process (" + call + ": " +
                   std::strerror(err) + ")");
}

// Forks a reader process, which runs `body` on its end of the channel (fds[1]) and does not
// return; here, closes that end and returns the process's id. fds[0] stays this process's.
template <typename Body>
pid_t fork_reader(const int (&fds)[2], const IsolatedOptions& options, const Body& body) {
  std::fflush(nullptr);  // no buffered output written twice, by parent and child
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw_cannot_start(options, "fork", err);
  }
  if (pid == 0) {
    ::close(fds[0]);
    body(fds[1]);
    ::_exit(3);  // not reached: body ends the process
  }
  ::close(fds[1]);
  return pid;
}

}  // namespace

std::string run_isolated(const std::function<std::string()>& work, const IsolatedOptions& options) {
  if (kForkOnlySingleThreaded && other_threads()) return in_this_process(work, options);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw_cannot_start(options, "pipe", errno);
  const pid_t pid = fork_reader(fds, options, [&](int fd) { child(fd, work); });

  std::string reply;
  Got got = Got::kEnd;
  try {
    got = receive(fds[0], reply, std::string::npos, options.max_reply_bytes,
                  std::chrono::steady_clock::now() + options.time_limit);
  } catch (...) {  // std::bad_alloc growing the reply: no child left behind
    ::close(fds[0]);
    ::kill(pid, SIGKILL);
    wait_for(pid);
    throw;
  }
  ::close(fds[0]);
  if (got == Got::kTimedOut || got == Got::kTooLong) ::kill(pid, SIGKILL);
  const int status = wait_for(pid);
  if (got == Got::kTooLong) throw_too_long(options);
  if (got == Got::kTimedOut) throw_timed_out(options);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || reply.empty()) throw_ended(status, options);
  return from_reply(std::move(reply), options);
}

// The worker's requests and replies on its socket: an 8-byte length, then that many bytes (a
// reply: reply_of's status byte, then the bytes or the message).
namespace {

bool send_framed(int fd, const std::string& bytes, int flags) {
  const std::uint64_t n = bytes.size();
  const auto send = [fd, flags](const char* d, std::size_t k) { return ::send(fd, d, k, flags); };
  return move_all(reinterpret_cast<const char*>(&n), sizeof n, send) &&
         move_all(bytes.data(), bytes.size(), send);
}

// Blocking: the worker waits for its next request. False at the end of the stream.
bool read_exactly(int fd, char* out, std::size_t n) {
  return move_all(out, n, [fd](char* d, std::size_t k) { return ::read(fd, d, k); });
}

[[noreturn]] void worker_loop(int fd, const IsolatedWorker::Handler& handler) {
  reader_process_signals();
  for (;;) {
    std::uint64_t n = 0;
    if (!read_exactly(fd, reinterpret_cast<char*>(&n), sizeof n)) ::_exit(0);  // caller gone
    std::string request(n, '\0');
    if (!read_exactly(fd, request.data(), request.size())) ::_exit(0);
    const std::string reply = reply_of([&] { return handler(request); });
    if (!send_framed(fd, reply, MSG_NOSIGNAL)) ::_exit(3);
  }
}

}  // namespace

IsolatedWorker::IsolatedWorker(Handler handler, std::size_t max_requests)
    : handler_(std::move(handler)), max_requests_(std::max<std::size_t>(max_requests, 1)) {}

IsolatedWorker::~IsolatedWorker() { stop(); }

void IsolatedWorker::stop() {
  if (pid_ < 0) return;
  ::kill(pid_, SIGKILL);
  wait_for(pid_);
  ::close(fd_);
  pid_ = -1;
  fd_ = -1;
}

void IsolatedWorker::start(const IsolatedOptions& options) {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    throw_cannot_start(options, "socketpair", errno);
  }
  pid_ = fork_reader(fds, options, [&](int fd) { worker_loop(fd, handler_); });
  fd_ = fds[0];
  served_ = 0;
}

std::string IsolatedWorker::call(const std::string& request, const IsolatedOptions& options) {
  if (kForkOnlySingleThreaded && other_threads()) {
    return in_this_process([&] { return handler_(request); }, options);
  }
  if (served_ >= max_requests_) stop();
  if (pid_ < 0) start(options);
  const auto deadline = std::chrono::steady_clock::now() + options.time_limit;
  if (!send_framed(fd_, request, MSG_NOSIGNAL)) {
    // The process ended between calls (killed from outside): another one takes the request.
    stop();
    start(options);
    if (!send_framed(fd_, request, MSG_NOSIGNAL)) {
      const int err = errno;
      stop();
      throw_cannot_start(options, "send", err);
    }
  }
  std::string head;
  std::string reply;
  Got got = Got::kEnd;
  try {
    got = receive(fd_, head, sizeof(std::uint64_t), sizeof(std::uint64_t), deadline);
    if (got == Got::kAll) {
      std::uint64_t n = 0;
      std::memcpy(&n, head.data(), sizeof n);
      if (n > options.max_reply_bytes) {
        got = Got::kTooLong;
      } else {
        reply.reserve(static_cast<std::size_t>(n));
        got = receive(fd_, reply, static_cast<std::size_t>(n), options.max_reply_bytes, deadline);
      }
    }
  } catch (...) {  // std::bad_alloc for the reply: its bytes are left unread, so no next call
    stop();
    throw;
  }
  if (got == Got::kAll) {
    ++served_;
    return from_reply(std::move(reply), options);
  }
  // The process ended, or is ended here: the next call starts another.
  if (got == Got::kEnd) {
    const int status = wait_for(pid_);
    ::close(fd_);
    pid_ = -1;
    fd_ = -1;
    throw_ended(status, options);
  }
  stop();
  if (got == Got::kTooLong) throw_too_long(options);
  throw_timed_out(options);
}

void ByteWriter::u64(std::uint64_t v) {
  bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// An empty Eigen vector's data() is null, and memcpy and append of no bytes from or to null
// are undefined (fuzzing finding 13: UBSan, a 0 x 5 .mat matrix read as a column).
void ByteWriter::f64(const double* values, std::size_t n) {
  if (n == 0) return;
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
  if (n == 0) return;
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
