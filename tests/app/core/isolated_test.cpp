// run_isolated (app/core/isolated.h): work in a child process, its bytes back, every way the
// child can end turned into an InputError naming the work.
#include "app/core/isolated.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
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

// No values, from and to the null pointer an empty Eigen vector's data() is: nothing written or
// read, the bytes around them intact (memcpy of none from null is undefined: fuzzing finding
// 13, which the sanitizer build of this test catches).
TEST(Isolated, NoValuesFromANullPointerRoundTrip) {
  ByteWriter w;
  w.u64(7);
  w.f64(nullptr, 0);
  w.u64(8);
  const std::string bytes = w.take();
  EXPECT_EQ(bytes.size(), 16u);
  ByteReader r(bytes, "reply");
  EXPECT_EQ(r.u64(), 7u);
  r.f64(nullptr, 0);
  EXPECT_EQ(r.u64(), 8u);
  EXPECT_EQ(r.left(), 0u);
}

// IsolatedWorker: one process answers many requests; each way it can end is the InputError
// run_isolated gives, and the next call starts another process.
std::string worker_message(IsolatedWorker& w, const std::string& request,
                           const IsolatedOptions& o) {
  try {
    w.call(request, o);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

// Whether process `pid` (a child of this one) has ended: a zombie, or gone (up to 10 s).
bool dead(pid_t pid) {
  for (int i = 0; i < 1000; ++i) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    if (!std::getline(stat, line)) return true;
    const auto paren = line.rfind(')');
    if (paren != std::string::npos && paren + 2 < line.size() && line[paren + 2] == 'Z') {
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// Whether `pid` was waited for already (no zombie left behind).
bool reaped(pid_t pid) {
  errno = 0;
  return ::waitpid(pid, nullptr, WNOHANG) == -1 && errno == ECHILD;
}

std::size_t open_descriptors() {
  return static_cast<std::size_t>(std::distance(
      std::filesystem::directory_iterator("/proc/self/fd"), std::filesystem::directory_iterator()));
}

// The handler's requests: "pid", "echo <text>", "big <n>", "abort", "exit", "sleep", "input",
// "other".
std::string handle(const std::string& request) {
  if (request == "pid") return std::to_string(::getpid());
  if (request.rfind("echo ", 0) == 0) return request.substr(5);
  if (request.rfind("big ", 0) == 0) return std::string(std::stoul(request.substr(4)), 'b');
  if (request == "abort") std::abort();
  if (request == "exit") ::_exit(7);
  if (request == "sleep") std::this_thread::sleep_for(std::chrono::seconds(60));
  if (request == "input") throw InputError("f.mat: variable 'x' is missing");
  throw std::runtime_error("unknown request " + request);
}

TEST(IsolatedWorker, OneProcessAnswersRequestsUpToItsCountThenAnother) {
  IsolatedWorker w(handle, 3);
  const auto o = named("w.mat: reading");
  EXPECT_EQ(w.pid(), -1);  // started by the first call
  const std::string first = w.call("pid", o);
  EXPECT_NE(first, std::to_string(::getpid()));
  EXPECT_EQ(std::to_string(w.pid()), first);
  EXPECT_EQ(w.call("echo abc", o), "abc");
  // 5 MB with every byte value, whole and in order, then a short one: framing holds.
  std::string big(5 * 1024 * 1024, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>(i * 131 % 256);
  EXPECT_EQ(w.call("echo " + big, o), big);
  // Three requests served: the fourth goes to a new process.
  const std::string second = w.call("pid", o);
  EXPECT_NE(second, first);
  EXPECT_EQ(w.call("echo ", o), "");
}

TEST(IsolatedWorker, ErrorsComeBackAsRunIsolatedGivesThemAndTheProcessGoesOn) {
  IsolatedWorker w(handle, 1000);
  const auto o = named("w.mat: reading");
  const std::string pid = w.call("pid", o);
  EXPECT_EQ(worker_message(w, "input", o), "f.mat: variable 'x' is missing");
  EXPECT_EQ(worker_message(w, "nonsense", o), "w.mat: reading: unknown request nonsense");
  EXPECT_EQ(w.call("pid", o), pid);  // an exception does not end the process
}

TEST(IsolatedWorker, AProcessThatDiesIsAnInputErrorAndTheNextCallStartsAnother) {
  IsolatedWorker w(handle, 1000);
  const auto o = named("w.mat: reading");
  const std::string pid = w.call("pid", o);
  const std::string aborted = worker_message(w, "abort", o);
  EXPECT_EQ(aborted.find("w.mat: reading: the reader process was ended by signal 6 (SIGABRT)"), 0u)
      << aborted;
  EXPECT_EQ(w.pid(), -1);
  EXPECT_TRUE(reaped(std::stoi(pid)));
  const std::string after = w.call("pid", o);
  EXPECT_NE(after, pid);
  const std::string exited = worker_message(w, "exit", o);
  EXPECT_EQ(exited.find("w.mat: reading: the reader process failed (exit status 7"), 0u) << exited;
  EXPECT_EQ(w.call("echo ok", o), "ok");
  // Killed from outside between two calls: the next request goes to a new process.
  const std::string victim = w.call("pid", o);
  ::kill(std::stoi(victim), SIGKILL);
  ASSERT_TRUE(dead(std::stoi(victim)));
  EXPECT_EQ(w.call("echo still", o), "still");
  EXPECT_NE(w.call("pid", o), victim);
  EXPECT_TRUE(reaped(std::stoi(victim)));
}

TEST(IsolatedWorker, TimeAndReplyLimitsStopTheProcess) {
  IsolatedWorker w(handle, 1000);
  IsolatedOptions o = named("h.mat: reading");
  const std::string pid = w.call("pid", o);
  IsolatedOptions short_limit = o;  // only for the call that sleeps: a fork may take longer
  short_limit.time_limit = std::chrono::milliseconds(300);
  EXPECT_EQ(worker_message(w, "sleep", short_limit),
            "h.mat: reading: not finished after 0.3 s; stopped (a damaged file?)");
  EXPECT_EQ(w.pid(), -1);
  EXPECT_TRUE(reaped(std::stoi(pid)));
  EXPECT_NE(w.call("pid", o), pid);
  // A reply of the limit exactly passes (the status byte counts), one byte more is stopped.
  IsolatedOptions k = named("k.mat: reading");
  k.max_reply_bytes = 1 << 20;
  const std::size_t payload = k.max_reply_bytes - 1;
  EXPECT_EQ(w.call("big " + std::to_string(payload), k).size(), payload);
  EXPECT_EQ(worker_message(w, "big " + std::to_string(payload + 1), k),
            "k.mat: reading: the reader process's reply passed 1048576 bytes; stopped (a "
            "damaged file declaring a huge array?)");
  EXPECT_EQ(w.call("echo next", k), "next");
}

// No descriptor and no process is left behind: by calls, by deaths and restarts, or by the
// worker's end.
TEST(IsolatedWorker, LeavesNoDescriptorOrProcessBehind) {
  const std::size_t before = open_descriptors();
  std::string last;
  {
    IsolatedWorker w(handle, 2);
    const auto o = named("w.mat: reading");
    for (int i = 0; i < 5; ++i) EXPECT_EQ(w.call("echo x", o), "x");  // two restarts
    worker_message(w, "abort", o);
    worker_message(w, "input", o);
    last = w.call("pid", o);
    EXPECT_EQ(open_descriptors(), before + 1);  // the running worker's socket
  }
  EXPECT_EQ(open_descriptors(), before);
  EXPECT_TRUE(reaped(std::stoi(last)));
  for (int i = 0; i < 3; ++i) run_isolated([] { return std::string("y"); }, named("r"));
  message_of([]() -> std::string { std::abort(); }, named("r"));
  EXPECT_EQ(open_descriptors(), before);
}

}  // namespace
}  // namespace chatterlab::app
