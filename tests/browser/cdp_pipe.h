// A headless Chromium driven over the DevTools protocol on a pipe (--remote-debugging-pipe:
// the browser reads commands on fd 3 and writes replies and events on fd 4, one JSON message
// per NUL-terminated chunk), for the report's browser test. No port is opened and no page
// other than the one the test navigates to is loaded.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace chatterlab::testing {

// The Chromium binary: /usr/bin/chromium, else `chromium` or `chromium-browser` in PATH; empty
// when none is installed.
inline std::filesystem::path find_chromium() {
  namespace fs = std::filesystem;
  if (fs::exists("/usr/bin/chromium")) return "/usr/bin/chromium";
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  std::size_t at = 0;
  while (at <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', at), dirs.size());
    const fs::path dir = dirs.substr(at, end - at);
    for (const char* name : {"chromium", "chromium-browser"}) {
      if (!dir.empty() && fs::exists(dir / name)) return dir / name;
    }
    at = end + 1;
  }
  return {};
}

inline std::vector<unsigned char> base64_decode(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  out.reserve(text.size() / 4 * 3);
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    const int v = value(c);
    if (v < 0) continue;  // '=' padding and whitespace
    bits = (bits << 6) | static_cast<std::uint32_t>(v);
    count += 6;
    if (count >= 8) {
      count -= 8;
      out.push_back(static_cast<unsigned char>((bits >> count) & 0xFF));
    }
  }
  return out;
}

// One browser process and the protocol session of one page in it.
class CdpBrowser {
 public:
  using json = nlohmann::json;
  using Clock = std::chrono::steady_clock;

  // Starts `chromium` with `flags` plus --remote-debugging-pipe; its stdout and stderr go to
  // `log_file`. Throws std::runtime_error when it cannot be started.
  CdpBrowser(const std::filesystem::path& chromium, const std::vector<std::string>& flags,
             const std::filesystem::path& log_file) {
    ::signal(SIGPIPE, SIG_IGN);  // a browser that dies makes write() fail instead
    int to_browser[2];
    int from_browser[2];
    if (::pipe2(to_browser, O_CLOEXEC) != 0 || ::pipe2(from_browser, O_CLOEXEC) != 0) {
      throw std::runtime_error("pipe2 failed");
    }
    // Above fd 10, so that the dup2 onto 3 and 4 cannot overwrite one another.
    const int child_in = ::fcntl(to_browser[0], F_DUPFD_CLOEXEC, 10);
    const int child_out = ::fcntl(from_browser[1], F_DUPFD_CLOEXEC, 10);
    ::close(to_browser[0]);
    ::close(from_browser[1]);
    write_fd_ = to_browser[1];
    read_fd_ = from_browser[0];

    std::vector<std::string> args{chromium.string()};
    args.insert(args.end(), flags.begin(), flags.end());
    args.push_back("--remote-debugging-pipe");
    args.push_back("about:blank");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    posix_spawn_file_actions_adddup2(&actions, child_in, 3);
    posix_spawn_file_actions_adddup2(&actions, child_out, 4);
    const int rc = ::posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(child_in);
    ::close(child_out);
    if (rc != 0) {
      pid_ = -1;
      throw std::runtime_error("cannot start " + chromium.string() + ": " + std::strerror(rc));
    }
  }

  ~CdpBrowser() { close(); }
  CdpBrowser(const CdpBrowser&) = delete;
  CdpBrowser& operator=(const CdpBrowser&) = delete;

  // Asks the browser to quit, and kills it (this process only, by its id) when it has not
  // within a few seconds.
  void close() {
    if (pid_ <= 0) return;
    try {
      send("Browser.close", json::object(), /*browser_level=*/true);
    } catch (...) {
    }
    const auto deadline = Clock::now() + std::chrono::seconds(5);
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (Clock::now() > deadline) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    pid_ = -1;
    ::close(write_fd_);
    ::close(read_fd_);
  }

  // Opens a new page and attaches to it; later commands go to that page.
  void open_page(std::chrono::milliseconds timeout) {
    const json target = call("Target.createTarget", {{"url", "about:blank"}}, timeout, true);
    const json attached =
        call("Target.attachToTarget", {{"targetId", target.at("targetId")}, {"flatten", true}},
             timeout, true);
    session_ = attached.at("sessionId").get<std::string>();
  }

  // Sends a command and waits for its reply; returns its "result". Throws on a protocol
  // error, a timeout or a browser that has gone.
  json call(const std::string& method, const json& params, std::chrono::milliseconds timeout,
            bool browser_level = false) {
    const int id = send(method, params, browser_level);
    const auto deadline = Clock::now() + timeout;
    for (;;) {
      std::optional<json> m = next_message(deadline);
      if (!m) throw std::runtime_error("no reply to " + method + " in time");
      if (m->contains("id") && (*m)["id"] == id) {
        if (m->contains("error")) {
          throw std::runtime_error(method + ": " + (*m)["error"].dump());
        }
        return m->value("result", json::object());
      }
    }
  }

  // Waits until `done` holds (checked after every message and at least every 100 ms);
  // returns false on timeout.
  bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (!done()) {
      if (Clock::now() > deadline) return false;
      next_message(std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
    }
    return true;
  }

  // Every event received so far (method and params), in order.
  const std::vector<json>& events() const { return events_; }
  Clock::time_point last_event_time() const { return last_event_; }

 private:
  int send(const std::string& method, const json& params, bool browser_level) {
    const int id = ++last_id_;
    json m{{"id", id}, {"method", method}, {"params", params}};
    if (!browser_level && !session_.empty()) m["sessionId"] = session_;
    std::string text = m.dump();
    text.push_back('\0');
    std::size_t at = 0;
    while (at < text.size()) {
      const ssize_t n = ::write(write_fd_, text.data() + at, text.size() - at);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw std::runtime_error("the browser has gone (write " + method + ")");
      at += static_cast<std::size_t>(n);
    }
    return id;
  }

  // The next message, keeping events; nullopt at the deadline.
  std::optional<json> next_message(Clock::time_point deadline) {
    for (;;) {
      const std::size_t nul = buffer_.find('\0');
      if (nul != std::string::npos) {
        json m = json::parse(buffer_.substr(0, nul));
        buffer_.erase(0, nul + 1);
        if (m.contains("method")) {
          events_.push_back(
              json{{"method", m["method"]}, {"params", m.value("params", json::object())}});
          last_event_ = Clock::now();
        }
        return m;
      }
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) return std::nullopt;
      pollfd p{read_fd_, POLLIN, 0};
      const int r = ::poll(&p, 1, static_cast<int>(left));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) return std::nullopt;
      char chunk[65536];
      const ssize_t n = ::read(read_fd_, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw std::runtime_error("the browser has gone (its pipe closed)");
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  pid_t pid_ = -1;
  int write_fd_ = -1;
  int read_fd_ = -1;
  int last_id_ = 0;
  std::string session_;
  std::string buffer_;
  std::vector<json> events_;
  Clock::time_point last_event_ = Clock::now();
};

}  // namespace chatterlab::testing
