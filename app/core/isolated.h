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
  // header declares a huge array (a v7.3 dataset stored as a fill value has no data to bound
  // it) must not make this process hold the array. 4 GiB: 500 M doubles, beyond any record
  // the program reads.
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
// process when other threads exist (isolated.cpp).
std::string run_isolated(const std::function<std::string()>& work, const IsolatedOptions& options);

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
