// Opens an HTML report in headless Chromium (tests/browser/cdp_pipe.h) the way a reader does,
// and measures it: the screenshot of the first screen, the resources it loads as opened and
// scrolled to the end, what more loads when every <details> is opened, images that do not
// load, links without a target, console errors and requests that left the machine.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/browser/cdp_pipe.h"

namespace chatterlab::testing {

struct LoadedResource {
  std::string url;
  std::string type;          // the protocol's resource type: Document, Stylesheet, Image, ...
  std::uintmax_t bytes = 0;  // the file's size on disk (file:// reports no transfer size)
  bool expanded = false;     // loaded only once every <details> was opened
};

struct ReportProbe {
  // Bytes of the page and everything it loaded as opened and scrolled to the end.
  std::uintmax_t screen_bytes = 0;
  // Bytes more when every <details> is opened and every lazy image is made to load.
  std::uintmax_t expanded_bytes = 0;
  std::vector<LoadedResource> resources;    // distinct URLs that finished loading
  std::vector<std::string> failed_loads;    // "url: net::ERR_..." for requests that failed
  std::vector<std::string> network_urls;    // requests to anything but file: and data:
  std::vector<std::string> broken_images;   // "src (why)"
  std::vector<std::string> broken_links;    // "href (why)"
  std::vector<std::string> console_errors;  // console.error, exceptions, browser log errors
  std::vector<std::string> console_warnings;
  int images = 0;                   // <img> elements in the page
  int images_loaded_as_opened = 0;  // of them, loaded after opening and scrolling to the end
  int in_page_links = 0;            // href="#..."
  int relative_refs = 0;            // href/src that resolve to a file
  int details = 0;                  // <details> elements, and of them closed as opened
  int details_closed = 0;
  int page_height_px = 0;
  std::vector<unsigned char> screenshot_png;  // the first screen, as opened
  // Each step of the probe and the seconds it took, in order, for the test's output.
  std::vector<std::pair<std::string, double>> steps;
};

namespace detail {

inline std::string percent_decode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

// The file of a file:// URL, without its query and fragment.
inline std::filesystem::path file_url_path(std::string url) {
  url = url.substr(std::string("file://").size());
  url = url.substr(0, url.find_first_of("?#"));
  return percent_decode(url);
}

inline std::string file_url(const std::filesystem::path& p) {
  std::string out = "file://";
  for (const unsigned char c : std::filesystem::absolute(p).lexically_normal().string()) {
    if (std::isalnum(c) || std::string("/-._~").find(static_cast<char>(c)) != std::string::npos) {
      out.push_back(static_cast<char>(c));
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

inline bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

// Scrolls the page to its end a step of 80 % of the window at a time, letting two frames
// render at each step so that lazy images near the viewport start loading; then scrolls to
// each shown image that has still not loaded, as a reader reaching it would. One call works
// for at most about 5 s and returns {done, height}; the caller calls again until done, so that
// a long page on a loaded machine never runs one protocol call into its timeout. The position
// reached is kept in the page between calls.
inline const char* kScrollToEnd = R"JS(
(async () => {
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
  const frame = () => Promise.race([new Promise((r) => requestAnimationFrame(r)), sleep(500)]);
  const settle = async () => { await frame(); await frame(); await sleep(20); };
  const el = document.scrollingElement || document.documentElement;
  const step = Math.max(100, Math.floor(window.innerHeight * 0.8));
  const t0 = performance.now();
  const s = window.__chatterlabScroll || (window.__chatterlabScroll = {y: 0, i: 0, image: 0});
  const more = () => performance.now() - t0 < 5000;
  for (; s.i < 5000 && more(); ++s.i, s.y += step) {
    window.scrollTo(0, s.y);
    await settle();
    if (s.y + window.innerHeight >= el.scrollHeight) { s.i = 5000; break; }
  }
  const shown = (i) => i.getClientRects().length > 0 && !i.closest('details:not([open])');
  const images = [...document.images];
  for (; s.i >= 5000 && s.image < images.length && more(); ++s.image) {
    const i = images[s.image];
    if (shown(i) && !(i.complete && i.naturalWidth > 0)) {
      i.scrollIntoView();
      await settle();
      await sleep(100);
    }
  }
  const done = s.i >= 5000 && s.image >= images.length;
  if (done) delete window.__chatterlabScroll;
  return {done: done, height: el.scrollHeight};
})()
)JS";

// The shown images (laid out, not inside a closed <details>) that have not loaded.
inline const char* kShownNotLoaded = R"JS(
[...document.images].filter((i) => i.getClientRects().length > 0 &&
    !i.closest('details:not([open])') && !(i.complete && i.naturalWidth > 0))
  .map((i) => i.getAttribute('src') || '')
)JS";

inline const char* kExpand = R"JS(
(() => {
  const all = [...document.querySelectorAll('details')];
  const closed = all.filter((d) => !d.open).length;
  all.forEach((d) => { d.open = true; });
  document.querySelectorAll('img').forEach((i) => { i.loading = 'eager'; });
  return {details: all.length, closed: closed};
})()
)JS";

inline const char* kImagesLoaded = R"JS(
[...document.images].filter((i) => i.complete && i.naturalWidth > 0).length
)JS";

inline const char* kCollect = R"JS(
(async () => {
  const images = await Promise.all([...document.images].map(async (i) => {
    let decoded = true;
    // An image that never decodes counts as not decoded after 10 s, not as a hung page.
    const late = new Promise((_, no) => setTimeout(() => no(new Error('late')), 10000));
    try { await Promise.race([i.decode(), late]); } catch (e) { decoded = false; }
    return {src: i.getAttribute('src') || '', complete: i.complete, width: i.naturalWidth,
            decoded: decoded};
  }));
  const inPage = [];
  const refs = [];
  for (const el of document.querySelectorAll('[href], [src]')) {
    for (const attr of ['href', 'src']) {
      const raw = el.getAttribute(attr);
      if (raw === null) continue;
      if (raw.startsWith('#')) {
        let id = raw.slice(1);
        try { id = decodeURIComponent(id); } catch (e) {}
        const ok = id === '' || id === 'top' || document.getElementById(id) !== null ||
                   document.getElementsByName(id).length > 0;
        inPage.push({href: raw, ok: ok});
        continue;
      }
      let url = '';
      try { url = new URL(raw, document.baseURI).href; } catch (e) { url = 'invalid:' + raw; }
      refs.push({raw: raw, url: url, tag: el.tagName.toLowerCase()});
    }
  }
  return {images: images, inPage: inPage, refs: refs};
})()
)JS";

}  // namespace detail

struct ProbeOptions {
  int width = 1280;
  int height = 900;
  std::chrono::milliseconds load_timeout{45000};
  std::chrono::milliseconds idle{600};  // no request in flight and no network event this long
  std::chrono::milliseconds idle_timeout{20000};
  // The whole scroll to the end, made of calls of about 5 s each (see kScrollToEnd).
  std::chrono::milliseconds scroll_timeout{300000};
};

// Loads `index_html` (a file) in `chromium`, with its profile and log under `work`.
// Throws std::runtime_error when the browser does not start or answer.
inline ReportProbe probe_report(const std::filesystem::path& chromium,
                                const std::filesystem::path& index_html,
                                const std::filesystem::path& work, const ProbeOptions& o = {}) {
  namespace fs = std::filesystem;
  using json = nlohmann::json;
  using std::chrono::milliseconds;
  const std::string size = std::to_string(o.width) + "," + std::to_string(o.height);
  CdpBrowser b(chromium,
               {"--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=" + size,
                "--force-device-scale-factor=1", "--hide-scrollbars", "--mute-audio",
                "--user-data-dir=" + (work / "chromium-profile").string(), "--no-first-run",
                "--no-default-browser-check", "--disable-extensions", "--disable-sync",
                "--disable-background-networking", "--disable-component-update",
                "--disable-default-apps", "--disable-features=Translate,MediaRouter",
                // Timers and frames at full rate, as for a reader's page in front: a loaded
                // machine must not make Chromium treat the page as in the background.
                "--disable-background-timer-throttling", "--disable-renderer-backgrounding",
                "--disable-backgrounding-occluded-windows",
                // Nothing from the network: no name resolves, and any other request goes to
                // a proxy on the loopback discard port, which refuses it.
                "--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9"},
               work / "chromium.log");
  const milliseconds t{15000};
  b.open_page(t);
  b.call("Emulation.setDeviceMetricsOverride",
         {{"width", o.width}, {"height", o.height}, {"deviceScaleFactor", 1}, {"mobile", false}},
         t);
  for (const char* domain : {"Page.enable", "Runtime.enable", "Log.enable", "Network.enable"}) {
    b.call(domain, json::object(), t);
  }
  b.call("Network.setCacheDisabled", {{"cacheDisabled", true}}, t);

  std::set<std::string> inflight;
  std::size_t seen = 0;
  auto track = [&]() {
    const auto& ev = b.events();
    for (; seen < ev.size(); ++seen) {
      const std::string m = ev[seen]["method"];
      const json& p = ev[seen]["params"];
      if (m == "Network.requestWillBeSent") inflight.insert(p.value("requestId", ""));
      if (m == "Network.loadingFinished" || m == "Network.loadingFailed") {
        inflight.erase(p.value("requestId", ""));
      }
    }
  };
  auto wait_idle = [&]() {
    b.wait_until(
        [&]() {
          track();
          return inflight.empty() && CdpBrowser::Clock::now() - b.last_event_time() > o.idle;
        },
        o.idle_timeout);
  };
  // The step under way, named in any error, and the time each step took.
  ReportProbe r;
  std::string step = "opening the page";
  auto step_start = CdpBrowser::Clock::now();
  auto begin_step = [&](const std::string& name) {
    const auto now = CdpBrowser::Clock::now();
    r.steps.emplace_back(step, std::chrono::duration<double>(now - step_start).count());
    step = name;
    step_start = now;
  };
  auto evaluate = [&](const std::string& js) {
    json reply;
    try {
      reply = b.call("Runtime.evaluate",
                     {{"expression", js}, {"awaitPromise", true}, {"returnByValue", true}},
                     o.load_timeout);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string(e.what()) + " while " + step);
    }
    if (reply.contains("exceptionDetails")) {
      throw std::runtime_error("page script failed while " + step + ": " +
                               reply["exceptionDetails"].dump());
    }
    return reply.at("result").value("value", json());
  };
  auto scroll_to_end = [&]() {
    const auto deadline = CdpBrowser::Clock::now() + o.scroll_timeout;
    for (int calls = 1;; ++calls) {
      const json s = evaluate(detail::kScrollToEnd);
      if (s.value("done", false)) return s.value("height", 0);
      if (CdpBrowser::Clock::now() > deadline) {
        throw std::runtime_error("the page did not scroll to its end in " +
                                 std::to_string(o.scroll_timeout.count() / 1000) + " s (" +
                                 std::to_string(calls) + " calls) while " + step);
      }
    }
  };

  const std::size_t navigate_at = b.events().size();
  const json nav = b.call("Page.navigate", {{"url", detail::file_url(index_html)}}, t);
  if (nav.contains("errorText")) {
    throw std::runtime_error("cannot open " + index_html.string() + ": " +
                             nav["errorText"].get<std::string>());
  }
  const bool loaded = b.wait_until(
      [&]() {
        for (std::size_t i = navigate_at; i < b.events().size(); ++i) {
          if (b.events()[i]["method"] == "Page.loadEventFired") return true;
        }
        return false;
      },
      o.load_timeout);
  if (!loaded) throw std::runtime_error("the page's load event did not come in time");
  begin_step("waiting for the loaded page to go idle");
  wait_idle();

  begin_step("taking the screenshot");
  const json shot = b.call("Page.captureScreenshot", {{"format", "png"}}, o.load_timeout);
  r.screenshot_png = base64_decode(shot.at("data").get<std::string>());

  begin_step("scrolling to the end as opened");
  r.page_height_px = scroll_to_end();
  begin_step("waiting for the scrolled page to go idle");
  wait_idle();
  begin_step("counting the images loaded");
  r.images_loaded_as_opened = evaluate(detail::kImagesLoaded).get<int>();
  std::set<std::string> not_loaded_when_shown;
  for (const json& src : evaluate(detail::kShownNotLoaded)) {
    not_loaded_when_shown.insert(src.get<std::string>());
  }
  const std::size_t expand_at = b.events().size();
  begin_step("opening every <details>");
  const json ex = evaluate(detail::kExpand);
  r.details = ex.value("details", 0);
  r.details_closed = ex.value("closed", 0);
  begin_step("scrolling to the end with every <details> open");
  scroll_to_end();
  begin_step("waiting for the expanded page to go idle");
  wait_idle();
  begin_step("collecting images and links");
  const json page = evaluate(detail::kCollect);
  begin_step("");

  // Resources: what the protocol saw requested, finished or failed.
  std::map<std::string, std::pair<std::string, std::string>> requests;  // id -> url, type
  std::map<std::string, bool> request_expanded;
  std::set<std::string> counted;
  const auto& ev = b.events();
  for (std::size_t i = 0; i < ev.size(); ++i) {
    const std::string m = ev[i]["method"];
    const json& p = ev[i]["params"];
    if (m == "Network.requestWillBeSent") {
      const std::string url = p["request"].value("url", "");
      requests[p.value("requestId", "")] = {url, p.value("type", "")};
      request_expanded[p.value("requestId", "")] = i >= expand_at;
      if (!detail::starts_with(url, "file:") && !detail::starts_with(url, "data:")) {
        r.network_urls.push_back(url);
      }
    } else if (m == "Network.loadingFinished") {
      const auto it = requests.find(p.value("requestId", ""));
      if (it == requests.end()) continue;
      const std::string& url = it->second.first;
      if (!detail::starts_with(url, "file:")) continue;
      const fs::path file = detail::file_url_path(url);
      if (!counted.insert(file.string()).second) continue;
      LoadedResource res{url, it->second.second, 0, request_expanded[it->first]};
      std::error_code e;
      res.bytes = fs::file_size(file, e);
      if (e) res.bytes = 0;
      (res.expanded ? r.expanded_bytes : r.screen_bytes) += res.bytes;
      r.resources.push_back(res);
    } else if (m == "Network.loadingFailed") {
      const auto it = requests.find(p.value("requestId", ""));
      r.failed_loads.push_back(
          (it == requests.end() ? p.value("requestId", "?") : it->second.first) + ": " +
          p.value("errorText", "failed"));
    } else if (m == "Log.entryAdded") {
      const json& e = p["entry"];
      const std::string line = e.value("source", "") + ": " + e.value("text", "") +
                               (e.contains("url") ? " (" + e.value("url", "") + ")" : "");
      if (e.value("level", "") == "error") r.console_errors.push_back(line);
      if (e.value("level", "") == "warning") r.console_warnings.push_back(line);
    } else if (m == "Runtime.consoleAPICalled") {
      std::string text = "console." + p.value("type", "") + ":";
      for (const json& a : p.value("args", json::array())) {
        text += " " + (a.contains("value") ? a["value"].dump() : a.value("description", ""));
      }
      const std::string type = p.value("type", "");
      if (type == "error" || type == "assert") r.console_errors.push_back(text);
      if (type == "warning") r.console_warnings.push_back(text);
    } else if (m == "Runtime.exceptionThrown") {
      const json& d = p["exceptionDetails"];
      r.console_errors.push_back(
          "exception: " + d.value("text", "") + " " +
          (d.contains("exception") ? d["exception"].value("description", "") : ""));
    }
  }

  // Images: every shown one loads when scrolled to, and every one loads once the <details> are
  // open and lazy ones are made to load.
  for (const json& img : page["images"]) {
    ++r.images;
    const bool complete = img.value("complete", false);
    const bool decoded = img.value("decoded", false);
    if (complete && decoded && img.value("width", 0) > 0) {
      if (not_loaded_when_shown.count(img.value("src", ""))) {
        r.broken_images.push_back(img.value("src", "") +
                                  " (shown, but loaded only when forced, not when scrolled to)");
      }
      continue;
    }
    r.broken_images.push_back(img.value("src", "") + " (" +
                              (!complete                    ? "never finished loading"
                               : img.value("width", 0) <= 0 ? "failed to load"
                                                            : "cannot be decoded") +
                              ")");
  }
  for (const json& l : page["inPage"]) {
    ++r.in_page_links;
    if (!l.value("ok", false)) {
      r.broken_links.push_back(l.value("href", "") + " (no element with that id or name)");
    }
  }
  for (const json& ref : page["refs"]) {
    const std::string url = ref.value("url", "");
    if (detail::starts_with(url, "file:")) {
      ++r.relative_refs;
      if (!fs::exists(detail::file_url_path(url))) {
        r.broken_links.push_back("<" + ref.value("tag", "") + "> " + ref.value("raw", "") +
                                 " (no such file)");
      }
    } else if (!detail::starts_with(url, "http:") && !detail::starts_with(url, "https:") &&
               !detail::starts_with(url, "mailto:") && !detail::starts_with(url, "data:")) {
      r.broken_links.push_back("<" + ref.value("tag", "") + "> " + ref.value("raw", "") +
                               " (not a URL)");
    }
  }
  b.close();
  return r;
}

// The width and height in a PNG's header; {0, 0} when `png` is not a PNG.
inline std::pair<int, int> png_size(const std::vector<unsigned char>& png) {
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (png.size() < 24 || !std::equal(sig, sig + 8, png.begin())) return {0, 0};
  auto be32 = [&](std::size_t at) {
    return static_cast<int>((png[at] << 24) | (png[at + 1] << 16) | (png[at + 2] << 8) |
                            png[at + 3]);
  };
  return {be32(16), be32(20)};
}

}  // namespace chatterlab::testing
