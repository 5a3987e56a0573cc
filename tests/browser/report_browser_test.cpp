// The demo report in a real browser (issue 15): headless Chromium opens the report of
// experiments/demo.synth.yaml from disk, scrolls it to the end and opens every <details>; no
// image fails to load, no link points nowhere, the console shows no error, nothing is
// requested from the network, and the page as opened transfers under 3 MB. The first screen
// is saved as a PNG for the docs. See docs/browser-test.md.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app/cli/run_binary.h"
#include "tests/browser/report_probe.h"

namespace chatterlab::testing {
namespace {

namespace fs = std::filesystem;

// The page as opened and scrolled to its end (HTML, CSS, every image that loads) must transfer
// less than this; content inside closed <details> is reported apart and not counted.
constexpr std::uintmax_t kMaxTransferBytes = 3'000'000;
constexpr int kScreenWidth = 1280;
constexpr int kScreenHeight = 900;

// Where the test writes what it keeps (the screenshot, the measurements), under the working
// directory ctest runs it in (the build's tests/ folder).
fs::path output_folder() { return fs::current_path() / "report_browser"; }

fs::path demo_spec() {
  // CHATTERLAB_TEST_DATA is <source>/tests/data.
  return (fs::path(CHATTERLAB_TEST_DATA).parent_path().parent_path() / "experiments" /
          "demo.synth.yaml")
      .lexically_normal();
}

std::string listed(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += "\n  " + i;
  return out;
}

std::string mb(std::uintmax_t bytes) {
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << static_cast<double>(bytes) / 1e6 << " MB";
  return s.str();
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Bytes per resource type, and the largest resources, for the test's output.
std::string breakdown(const ReportProbe& r, bool expanded) {
  std::map<std::string, std::pair<int, std::uintmax_t>> by_type;
  std::vector<LoadedResource> list;
  for (const auto& res : r.resources) {
    if (res.expanded != expanded) continue;
    auto& t = by_type[res.type];
    ++t.first;
    t.second += res.bytes;
    list.push_back(res);
  }
  std::ostringstream s;
  for (const auto& [type, t] : by_type) {
    s << "    " << type << ": " << t.first << " files, " << t.second << " bytes\n";
  }
  std::sort(list.begin(), list.end(),
            [](const LoadedResource& a, const LoadedResource& b) { return a.bytes > b.bytes; });
  if (list.size() > 8) list.resize(8);
  for (const auto& res : list) {
    s << "    " << res.bytes << "  " << res.url.substr(res.url.find_last_of('/') + 1) << "\n";
  }
  return s.str();
}

TEST(ReportBrowser, DemoReportLoadsCleanlyInHeadlessChromium) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path chromium = find_chromium();
  ASSERT_FALSE(chromium.empty())
      << "Chromium is not installed (looked for /usr/bin/chromium, chromium and "
         "chromium-browser in PATH): run scripts/install-deps.sh, which installs the Debian "
         "package `chromium` that this test needs.";
  ASSERT_TRUE(fs::exists(demo_spec())) << demo_spec();

  const fs::path out = output_folder();
  const fs::path work = out / ("work-" + std::to_string(::getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code e;
      fs::remove_all(dir, e);
    }
  } cleanup{work};

  const fs::path campaign = work / "demo";
  const fs::path report = work / "report";
  const BinaryRun synth = run_chatterlab(
      "synth " + quoted(demo_spec()) + " --out " + quoted(campaign) + " --quiet", work);
  ASSERT_EQ(synth.status, 0) << synth.err;
  const BinaryRun rep = run_chatterlab(
      "report " + quoted(campaign) + " --out " + quoted(report) + " --no-pdf --quiet", work);
  ASSERT_EQ(rep.status, 0) << rep.err;
  ASSERT_TRUE(fs::exists(report / "index.html"));
  const double report_s = seconds_since(t0);

  ProbeOptions options;
  options.width = kScreenWidth;
  options.height = kScreenHeight;
  ReportProbe r;
  try {
    r = probe_report(chromium, report / "index.html", work, options);
  } catch (const std::exception& e) {
    FAIL() << "headless Chromium (" << chromium << ") could not open the report: " << e.what()
           << "\n"
           << file_text(work / "chromium.log").substr(0, 4000);
  }
  const double total_s = seconds_since(t0);

  // The screenshot of the first screen, kept for the docs.
  const fs::path shot = out / "report-first-screen.png";
  std::ofstream(shot, std::ios::binary)
      .write(reinterpret_cast<const char*>(r.screenshot_png.data()),
             static_cast<std::streamsize>(r.screenshot_png.size()));

  int screen_resources = 0;
  for (const auto& res : r.resources) screen_resources += res.expanded ? 0 : 1;
  std::cout << "[ report   ] demo synthesized and reported in " << report_s
            << " s; browser checks done at " << total_s << " s\n"
            << "[ transfer ] as opened and scrolled to the end: " << r.screen_bytes << " bytes ("
            << mb(r.screen_bytes) << ", limit " << mb(kMaxTransferBytes) << ") in "
            << screen_resources << " files\n"
            << breakdown(r, false) << "[ expanded ] more with every <details> opened ("
            << r.details_closed << " of " << r.details << " closed as opened): " << r.expanded_bytes
            << " bytes in " << r.resources.size() - screen_resources << " files\n"
            << breakdown(r, true) << "[ page     ] " << r.page_height_px << " px tall; " << r.images
            << " images, " << r.images_loaded_as_opened << " loaded as opened and scrolled; "
            << r.in_page_links << " in-page links, " << r.relative_refs
            << " relative links and sources\n"
            << "[ problems ] " << r.broken_images.size() << " broken images, "
            << r.broken_links.size() << " broken links, " << r.console_errors.size()
            << " console errors, " << r.console_warnings.size() << " console warnings, "
            << r.failed_loads.size() << " failed loads, " << r.network_urls.size()
            << " network requests\n"
            << "[ shot     ] " << shot.string() << "\n";
  for (const auto& [name, seconds] : r.steps) {
    std::cout << "[ step     ] " << seconds << " s " << name << "\n";
  }

  nlohmann::json m{{"screen_bytes", r.screen_bytes},
                   {"expanded_bytes", r.expanded_bytes},
                   {"limit_bytes", kMaxTransferBytes},
                   {"images", r.images},
                   {"images_loaded_as_opened", r.images_loaded_as_opened},
                   {"details", r.details},
                   {"details_closed", r.details_closed},
                   {"broken_images", r.broken_images},
                   {"broken_links", r.broken_links},
                   {"console_errors", r.console_errors},
                   {"console_warnings", r.console_warnings},
                   {"failed_loads", r.failed_loads},
                   {"network_urls", r.network_urls},
                   {"seconds", total_s},
                   {"step_seconds", r.steps}};
  std::ofstream(out / "measurements.json") << m.dump(2) << "\n";

  EXPECT_TRUE(r.broken_images.empty()) << r.broken_images.size() << " of " << r.images
                                       << " images did not load:" << listed(r.broken_images);
  EXPECT_TRUE(r.broken_links.empty())
      << r.broken_links.size() << " links or sources point nowhere:" << listed(r.broken_links);
  EXPECT_TRUE(r.console_errors.empty())
      << r.console_errors.size() << " console errors:" << listed(r.console_errors);
  EXPECT_TRUE(r.failed_loads.empty()) << "failed loads:" << listed(r.failed_loads);
  EXPECT_TRUE(r.network_urls.empty())
      << "requests that are not to a local file:" << listed(r.network_urls);
  EXPECT_LT(r.screen_bytes, kMaxTransferBytes)
      << "the report as opened and scrolled to the end transfers " << r.screen_bytes
      << " bytes; largest files:\n"
      << breakdown(r, false);

  const auto [w, h] = png_size(r.screenshot_png);
  EXPECT_EQ(w, kScreenWidth) << shot;
  EXPECT_EQ(h, kScreenHeight) << shot;
  EXPECT_GT(fs::file_size(shot), 1000u) << shot;
}

}  // namespace
}  // namespace chatterlab::testing
