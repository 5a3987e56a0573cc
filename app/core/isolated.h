// Runs a piece of work in a child process (fork, no exec), so that a crash, a hang or memory
// corruption inside a third-party parser of untrusted files (libhdf5, under libmatio, for
// v7.3 .mat files: fuzzing finding 8, docs/fuzzing.md) ends that child, not the run. The
// work's result comes back through a pipe as bytes.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

namespace chatterlab::app {

struct IsolatedOptions {
  // What the messages call the work, e.g. "data/run.mat: reading this v7.3 .mat file".
  std::string what;
  // The child is killed after this long (a parser caught in a loop).
  std::chrono::milliseconds time_limit{std::chrono::seconds(120)};
  // The child is killed when its reply grows past this many bytes: a damaged file whose
  // header declares a huge array must not make this process hold the array (the .mat reader
  // bounds what a variable may declare by its file's size, 1,100 values a byte, which a large
  // file still passes). 4 GiB: 500 M doubles, beyond any record the program reads.
  std::size_t max_reply_bytes = std::size_t{4} << 30;
};

// Calls work() in a child process and returns the bytes it returned. An InputError thrown by
// work() is thrown again here with its message; any other exception becomes an InputError
// with `what` and its message. A child that dies (a signal, a sanitizer report), exits without
// a reply, outlives the time limit or replies more than max_reply_bytes gives an InputError
// naming `what` and how it ended.
// The caller must hold whatever locks work() needs: the child has only the calling thread,
// and must not take a lock another thread may have held at the fork. In a build with GCC's
// AddressSanitizer (make sanitize), whose allocator is not fork-safe, work() runs in this
// process when other threads exist (isolated.cpp). Calls from several threads must be
// serialized by the caller (the .mat readers hold one lock): a process forked during another
// call would hold that call's descriptors, and the other call would wait out its time limit.
// In the child, crash and termination signals take their default action (isolated.cpp,
// reader_process_signals): a crash is reported as the signal it was.
std::string run_isolated(const std::function<std::string()>& work, const IsolatedOptions& options);

// One reader process kept for many requests, for a caller that reads thousands of small files
// a second (the .mat fuzz target: docs/fuzzing.md, "Speed"), where a fork per read would cost
// more than the read. The handler, fixed when the worker is made, runs in the worker process on
// each request's bytes; the process is started on the first call, after one that ended it
// (a crash, a time limit, a reply past the limit) and after max_requests requests, so that what
// a damaged file left in a library's state does not last. Each call's outcome is what
// run_isolated gives for the same work, with the same messages. A failure stays contained, but
// a request may see state an earlier one left in the process: the program reads with
// run_isolated, one fresh process per read.
class IsolatedWorker {
 public:
  using Handler = std::function<std::string(const std::string& request)>;
  IsolatedWorker(Handler handler, std::size_t max_requests);
  ~IsolatedWorker();
  IsolatedWorker(const IsolatedWorker&) = delete;
  IsolatedWorker& operator=(const IsolatedWorker&) = delete;

  // The handler's reply to `request`, computed in the worker process; errors as run_isolated.
  std::string call(const std::string& request, const IsolatedOptions& options);

  // The worker process's id, or -1 when none is running (for tests).
  int pid() const { return pid_; }

 private:
  void start(const IsolatedOptions& options);
  void stop();  // kills the worker and waits for it
  Handler handler_;
  std::size_t max_requests_;
  std::size_t served_ = 0;  // requests the running process has answered
  int pid_ = -1;
  int fd_ = -1;  // this end of the worker's socket
};

// Little helpers to pass values through the bytes: fixed-width integers and doubles in the
// machine's byte order (parent and child are the same program), strings with their length.
class ByteWriter {
 public:
  void u64(std::uint64_t v);
  void f64(const double* values, std::size_t n);
  void str(const std::string& s);
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

// Reads what ByteWriter wrote; throws InputError naming `what` when the bytes run short.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
  std::uint64_t u64();
  void f64(double* out, std::size_t n);
  std::string str();
  std::size_t left() const { return bytes_.size() - pos_; }
  const std::string& what() const { return what_; }

 private:
  void need(std::size_t n) const;
  const std::string& bytes_;
  std::string what_;
  std::size_t pos_ = 0;
};

}  // namespace chatterlab::app
