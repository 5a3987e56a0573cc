// run_isolated (app/core/isolated.h): work in a child process, its bytes back, every way the
// child can end turned into an InputError naming the work.
#include "app/core/isolated.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

#include "analysis/common/summary.h"

namespace chatterlab::app {
namespace {

IsolatedOptions named(const std::string& what) {
  IsolatedOptions o;
  o.what = what;
  return o;
}

std::string message_of(const std::function<std::string()>& work, const IsolatedOptions& o) {
  try {
    run_isolated(work, o);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(Isolated, ReturnsTheBytesTheChildProduced) {
  // 5 MB with every byte value: more than a pipe buffer, read back whole and in order.
  std::string big(5 * 1024 * 1024, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>(i * 131 % 256);
  EXPECT_EQ(run_isolated([&] { return big; }, named("big")), big);
  EXPECT_EQ(run_isolated([] { return std::string(); }, named("empty")), "");
}

TEST(Isolated, WorkRunsInAnotherProcess) {
  const pid_t parent = ::getpid();
  const std::string child = run_isolated([] { return std::to_string(::getpid()); }, named("pid"));
  EXPECT_NE(child, std::to_string(parent));
  int touched = 0;
  run_isolated(
      [&] {
        touched = 1;  // the child's copy
        return std::string();
      },
      named("copy"));
  EXPECT_EQ(touched, 0);
}

// With another thread running: a child process in every build but GCC's AddressSanitizer one,
// where the work runs in this process (its allocator is not fork-safe; isolated.cpp).
TEST(Isolated, WithOtherThreadsTheWorkRunsInAChildUnlessUnderGccAsan) {
  std::atomic<bool> stop{false};
  std::thread other([&] {
    while (!stop) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  const std::string pid = run_isolated([] { return std::to_string(::getpid()); }, named("pid"));
  // The reply is decoded alike on both paths: bytes, an input error, another error.
  const std::string input_error = message_of(
      []() -> std::string { throw InputError("f.mat: variable 'x' is missing"); }, named("f.mat"));
  const std::string other_error =
      message_of([]() -> std::string { throw std::runtime_error("boom"); }, named("f.mat"));
  stop = true;
  other.join();
  EXPECT_EQ(input_error, "f.mat: variable 'x' is missing");
  EXPECT_EQ(other_error, "f.mat: boom");
#if defined(__SANITIZE_ADDRESS__) && !defined(__clang__)
  EXPECT_EQ(pid, std::to_string(::getpid()));
#else
  EXPECT_NE(pid, std::to_string(::getpid()));
#endif
}

TEST(Isolated, InputErrorComesBackWithItsMessage) {
  EXPECT_EQ(message_of([]() -> std::string { throw InputError("f.mat: variable 'x' is missing"); },
                       named("f.mat: reading")),
            "f.mat: variable 'x' is missing");
}

TEST(Isolated, OtherExceptionsBecomeInputErrorsNamingTheWork) {
  EXPECT_EQ(message_of([]() -> std::string { throw std::runtime_error("bad_alloc-like"); },
                       named("f.mat: reading")),
            "f.mat: reading: bad_alloc-like");
}

TEST(Isolated, AChildThatDiesIsAnInputErrorNotTheEndOfTheRun) {
  // abort: SIGABRT in every build (the sanitizers do not take over abort).
  const std::string aborted =
      message_of([]() -> std::string { std::abort(); }, named("f.mat: reading"));
  EXPECT_EQ(aborted.find("f.mat: reading: the reader process was ended by signal 6 (SIGABRT)"), 0u)
      << aborted;
  const std::string exited =
      message_of([]() -> std::string { ::_exit(7); }, named("g.mat: reading"));
  EXPECT_EQ(exited.find("g.mat: reading: the reader process failed (exit status 7"), 0u) << exited;
}

TEST(Isolated, AChildPastItsTimeLimitIsKilled) {
  IsolatedOptions o = named("h.mat: reading");
  o.time_limit = std::chrono::milliseconds(300);
  const std::string msg = message_of(
      []() -> std::string {
        std::this_thread::sleep_for(std::chrono::seconds(60));
        return "late";
      },
      o);
  EXPECT_EQ(msg, "h.mat: reading: not finished after 0.3 s; stopped (a damaged file?)");
}

// A reply may reach max_reply_bytes exactly; one byte more and the child is stopped.
TEST(Isolated, AReplyPastTheLimitIsStopped) {
  IsolatedOptions o = named("k.mat: reading");
  o.max_reply_bytes = 1 << 20;
  const std::size_t payload = o.max_reply_bytes - 1;  // plus the status byte: the limit exactly
  EXPECT_EQ(run_isolated([&] { return std::string(payload, 'a'); }, o).size(), payload);
  const std::string msg = message_of([&] { return std::string(payload + 1, 'a'); }, o);
  EXPECT_EQ(msg,
            "k.mat: reading: the reader process's reply passed 1048576 bytes; stopped (a "
            "damaged file declaring a huge array?)");
}

TEST(Isolated, BytesRoundTripAndAShortReplyIsAnError) {
  ByteWriter w;
  w.u64(42);
  w.str("name");
  const double v[3] = {1.5, -2.0, 1e300};
  w.f64(v, 3);
  const std::string bytes = w.take();
  ByteReader r(bytes, "reply");
  EXPECT_EQ(r.u64(), 42u);
  EXPECT_EQ(r.str(), "name");
  double out[3];
  r.f64(out, 3);
  EXPECT_EQ(out[0], 1.5);
  EXPECT_EQ(out[1], -2.0);
  EXPECT_EQ(out[2], 1e300);
  EXPECT_EQ(r.left(), 0u);
  EXPECT_THROW(r.u64(), InputError);
  const std::string cut = bytes.substr(0, 10);  // the string's length, then too few bytes
  ByteReader s(cut, "reply");
  s.u64();
  EXPECT_THROW(s.str(), InputError);
}

}  // namespace
}  // namespace chatterlab::app
