// Data out (issue 15): the files a report writes beside results.json for other tools: every
// tap FRF as CSV and UFF58, the data behind every figure as CSV, the identified values as CSV,
// each named in results.json (a test's or group's figures in its `figures`); and the figure CSV
// holds the series the figure drew, to 9 significant digits.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/core/campaign.h"
#include "app/formats/frf_text.h"
#include "app/formats/uff58.h"
#include "app/kinds/tap/tap_kind.h"
#include "app/pipeline/campaign_values.h"
#include "app/report/figure_jobs.h"
#include "app/report/report.h"
#include "app/report/results_json.h"
#include "app/synth/synth.h"
#include "render/temp_dir.h"
#include "tests/support/synth_spec.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using nlohmann::json;

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::vector<std::string> split(const std::string& s, char d = ',') {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (char c : s) {
    if (c == '"') {
      quoted = !quoted;
      continue;
    }
    if (c == d && !quoted) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

double value(const std::string& s) { return s.empty() ? std::nan("") : std::stod(s); }

// panel (1-based) -> series label -> (x, y), from a figure CSV.
struct FigureData {
  std::vector<std::string> comments;
  std::map<int, std::map<std::string, std::pair<std::vector<double>, std::vector<double>>>> series;
};

FigureData read_figure_csv(const fs::path& p) {
  FigureData d;
  bool header = false;
  for (const auto& l : lines_of(p)) {
    if (l.rfind("# ", 0) == 0) {
      d.comments.push_back(l);
      continue;
    }
    if (!header) {
      EXPECT_EQ(l, "panel,series,x,y");
      header = true;
      continue;
    }
    const auto f = split(l);
    EXPECT_EQ(f.size(), 4u) << l;
    if (f.size() != 4) continue;
    auto& s = d.series[std::stoi(f[0])][f[1]];
    s.first.push_back(value(f[2]));
    s.second.push_back(value(f[3]));
  }
  return d;
}

// `b` is `a` as the figure CSV writes it: 9 significant digits (%.9g), so within half a unit of
// the 9th digit, 5e-9 relative.
void expect_same(const std::vector<double>& a, const std::vector<double>& b,
                 const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i])) {
      EXPECT_TRUE(std::isnan(b[i])) << what << " [" << i << "]";
    } else {
      EXPECT_LE(std::abs(a[i] - b[i]), 5e-9 * std::abs(a[i])) << what << " [" << i << "]";
    }
  }
}

// Every figure file of the report folder, relative to it ("figures/x.csv").
std::set<std::string> figure_files_in(const fs::path& out) {
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(out / "figures")) {
    files.insert("figures/" + e.path().filename().string());
  }
  return files;
}

// The figure files results.json names in `figures` of every test and group entry; each must
// exist and end in the extension its key names, and an entry only holds analysed blocks.
std::set<std::string> figure_files_named(const json& r, const fs::path& out) {
  std::set<std::string> named;
  const auto collect = [&](const std::string& where, const json& entry) {
    if (entry.value("status", "ok") != "ok") {
      EXPECT_FALSE(entry.contains("figures")) << where;
      return;
    }
    EXPECT_TRUE(entry.contains("figures")) << where;
    const json figures = entry.value("figures", json::object());
    for (const auto& [key, files] : figures.items()) {
      EXPECT_FALSE(files.empty()) << where << " " << key;
      for (const auto& [ext, path] : files.items()) {
        const std::string p = path.get<std::string>();
        EXPECT_EQ(p.rfind("figures/", 0), 0u) << where << " " << key << ": " << p;
        EXPECT_EQ(p.substr(p.size() - ext.size() - 1), "." + ext) << where << " " << key;
        EXPECT_TRUE(fs::is_regular_file(out / p)) << where << " " << key << ": " << p;
        EXPECT_TRUE(named.insert(p).second) << p << " named twice";
      }
    }
  };
  for (const auto& [id, t] : r.at("tests").items()) collect("tests." + id, t);
  for (const auto& [name, g] : r.at("groups").items()) collect("groups." + name, g);
  return named;
}

// Every figure file written is named, and every name is a file written.
void expect_every_figure_file_named(const json& r, const fs::path& out) {
  const std::set<std::string> written = figure_files_in(out);
  const std::set<std::string> named = figure_files_named(r, out);
  for (const auto& f : written) EXPECT_TRUE(named.count(f)) << f << " is written but not named";
  EXPECT_EQ(named.size(), written.size());
  std::size_t csv = 0;
  for (const auto& f : named) csv += f.size() > 4 && f.substr(f.size() - 4) == ".csv";
  EXPECT_GE(csv, 1u);
}

TEST(FigureCsv, LongFormatWithLabelsNaNAndQuotedNames) {
  render::Figure fig;
  fig.share_x = true;
  render::Axes& a = fig.panels.emplace_back();
  a.y_label = "|H| [m/N]";
  a.log_x = a.log_y = true;
  a.series.push_back({{1.0, 2.0, 3.0}, {0.1, std::nan(""), 1.0 / 3.0}, "H1, averaged"});
  a.series.push_back({{1.0}, {2.0}, ""});
  render::Axes& b = fig.panels.emplace_back();
  b.x_label = "frequency [Hz]";
  b.y_label = "coherence [-]";
  b.series.push_back({{1.0, 2.0}, {0.5, 1.0}, "coh \"x\""});
  TempDir d;
  write_figure_csv(fig, d.path() / "f.csv", "figures/f");
  const auto lines = lines_of(d.path() / "f.csv");
  ASSERT_EQ(lines.size(), 10u);
  EXPECT_EQ(lines[0], "# chatterlab figure data: figures/f");
  EXPECT_EQ(lines[1], "# panel 1: x = frequency [Hz] (log), y = |H| [m/N] (log)");
  EXPECT_EQ(lines[2], "# panel 2: x = frequency [Hz], y = coherence [-]");
  EXPECT_EQ(lines[3], "panel,series,x,y");
  EXPECT_EQ(lines[4], "1,\"H1, averaged\",1,0.1");  // 9 significant digits at most
  EXPECT_EQ(lines[5], "1,\"H1, averaged\",2,");
  EXPECT_EQ(lines[6], "1,\"H1, averaged\",3,0.333333333");
  EXPECT_EQ(lines[7], "1,series 2,1,2");
  EXPECT_EQ(lines[8], "2,\"coh \"\"x\"\"\",1,0.5");
}

// Tap tests on x and y, the dyno-slot group and one short constant-depth cut with a short
// identification: every kind that writes files, in a few seconds.
TEST(ReportFiles, FrfFigureAndIdentifiedFilesBesideResultsJson) {
  TempDir d;
  chatterlab::testing::SynthSpecText st;
  st.name = "files-check";
  st.seed = 3;
  st.tap_sample_rate_hz = 12800;
  st.tap_hit_spacing_s = 0.5;
  st.dyno_duration_s = 0.5;
  st.cut_air_revolutions = 10;
  st.cut_tests =
      "    - {name: constant, axial_depth_mm: 1.0, duration_s: 0.1, offset_angle_deg: 147.0}\n";
  const fs::path spec = d.write("spec.yaml", st.text());
  const fs::path campaign = d.path() / "campaign";
  const fs::path out = d.path() / "report";
  synthesize_campaign(spec, campaign);
  std::ofstream(campaign / "campaign.yaml", std::ios::app)
      << "estimation: {window_s: 0.02, max_passes: 1, repeat_runs: 0, settle_revolutions: 5}\n";
  std::ostringstream log;
  ReportOptions opt;
  opt.pdf = false;
  opt.jobs = 2;
  ASSERT_EQ(run_report(campaign, out, opt, log), 0) << log.str();
  std::ifstream rin(out / "results.json");
  const json r = json::parse(rin);

  // Tap FRFs: CSV and UFF58, named in the test's block.
  for (const std::string id : {"tap/x", "tap/y"}) {
    const json& t = r["tests"][id];
    ASSERT_EQ(t["status"], "ok") << t.dump();
    EXPECT_EQ(t["frf_source"], "hits");
    ASSERT_EQ(t["frf_csv"], id + "/frf.csv");
    ASSERT_EQ(t["frf_uff"], id + "/frf.uff");
    const auto lines = lines_of(out / (id + "/frf.csv"));
    ASSERT_GT(lines.size(), 100u);
    std::size_t header = 0;
    while (header < lines.size() && lines[header].rfind("# ", 0) == 0) ++header;
    ASSERT_LT(header, lines.size());
    EXPECT_EQ(lines[header], "f_hz,re,im,coherence,h2_re,h2_im,fit_re,fit_im");
    const std::size_t rows = lines.size() - header - 1;
    for (std::size_t i = header + 1; i < lines.size(); ++i) {
      ASSERT_EQ(split(lines[i]).size(), 8u) << lines[i];
    }
    const double df = t["frequency_resolution_hz"];
    EXPECT_DOUBLE_EQ(value(split(lines[header + 1])[0]), df);  // bin 1
    const auto functions = uff::read_uff58(out / (id + "/frf.uff"));
    ASSERT_EQ(functions.size(), 4u);  // H1, H2, fit, coherence
    EXPECT_EQ(functions[0].id1, "H1 " + id);
    EXPECT_EQ(functions[0].function_type, uff::kFrf);
    EXPECT_EQ(functions[0].response_direction, id == "tap/x" ? 1 : 2);
    EXPECT_EQ(functions[2].id1, "fit " + id);
    EXPECT_EQ(functions[3].function_type, uff::kCoherence);
    for (const auto& f : functions) EXPECT_EQ(static_cast<std::size_t>(f.samples()), rows);
    // The CSV reads back as an FRF input.
    const auto table = frf_text::read_frf_text(out / (id + "/frf.csv"), id);
    EXPECT_EQ(static_cast<std::size_t>(table.f_hz.size()), rows);
    EXPECT_EQ(table.coherence.size(), table.f_hz.size());
    // The FRF figure and its data, named like every figure in the test's `figures`.
    const std::string stem =
        "figures/tap-" + std::string(id == "tap/x" ? "tap-x" : "tap-y") + "-frf";
    EXPECT_EQ(t["figures"]["frf"],
              json({{"svg", stem + ".svg"}, {"png", stem + ".png"}, {"csv", stem + ".csv"}}));
    EXPECT_FALSE(t.contains("figure_data"));
  }
  // Every test and group names the figure files it has, and nothing else is in figures/.
  expect_every_figure_file_named(r, out);
  EXPECT_FALSE(r["groups"]["dyno-slot"]["figures"].empty());
  EXPECT_FALSE(r["tests"]["cuts/constant"]["figures"].empty());

  // Every figure has its data beside it.
  int figures = 0;
  for (const auto& e : fs::directory_iterator(out / "figures")) {
    if (e.path().extension() != ".svg") continue;
    ++figures;
    fs::path csv = e.path();
    csv.replace_extension(".csv");
    ASSERT_TRUE(fs::exists(csv)) << csv.filename();
    const auto lines = lines_of(csv);
    ASSERT_GE(lines.size(), 3u);
    EXPECT_EQ(lines[0].rfind("# chatterlab figure data: figures/", 0), 0u) << lines[0];
  }
  EXPECT_GE(figures, 4);

  // The tap figure's CSV holds the series the figure was drawn from: the same test run again
  // (deterministic) gives the figure model.
  const CampaignSpec c = load_campaign(campaign);
  for (const auto& t : c.tests) {
    if (t.id != "tap/x") continue;
    TestOutcome o;
    o.spec = &t;
    TapKind().run(t, CampaignValues{}, RunContext{}, o);
    ASSERT_TRUE(o.status.ok());
    const render::Figure fig = tap_frf_figure(o.result_of<TapOutcome>());
    const FigureData data = read_figure_csv(out / "figures/tap-tap-x-frf.csv");
    EXPECT_EQ(data.comments.at(1),
              "# panel 1: x = frequency [Hz] (log), y = |receptance| [m/N] (log)");
    ASSERT_EQ(data.series.size(), fig.panels.size());
    for (std::size_t p = 0; p < fig.panels.size(); ++p) {
      const auto& panel = data.series.at(static_cast<int>(p + 1));
      ASSERT_EQ(panel.size(), fig.panels[p].series.size());
      for (const auto& s : fig.panels[p].series) {
        const auto& got = panel.at(s.label);
        expect_same(s.x, got.first, s.label + " x");
        expect_same(s.y, got.second, s.label + " y");
      }
    }
  }

  // The identified values: one row per value of results.json `identified`, the same numbers, and
  // its `_ci95` pair in the last two columns (the joint estimate's intervals).
  ASSERT_TRUE(r.contains("identified_csv")) << r["identified"].dump();
  const std::string ic = r["identified_csv"];
  EXPECT_EQ(ic, r["identified_from"].get<std::string>() + "/identified.csv");
  EXPECT_EQ(r["tests"][r["identified_from"].get<std::string>()]["identified_csv"], ic);
  const auto lines = lines_of(out / ic);
  ASSERT_GE(lines.size(), 4u);
  EXPECT_EQ(r["identified_method"], "joint");
  EXPECT_EQ(lines[1], "# method: joint (95 % intervals in ci95_lo, ci95_hi)");
  EXPECT_EQ(lines[2], "quantity,value,unit,ci95_lo,ci95_hi");
  const json& id = r["identified"];
  std::size_t values = 0, intervals = 0;
  for (const auto& [key, v] : id.items())
    (key.size() > 5 && key.substr(key.size() - 5) == "_ci95" ? intervals : values)++;
  EXPECT_EQ(lines.size() - 3, values);
  EXPECT_EQ(intervals, values - 1);  // every value but k_N_m, held
  std::map<std::string, std::string> units;
  for (std::size_t i = 3; i < lines.size(); ++i) {
    const auto f = split(lines[i]);
    ASSERT_EQ(f.size(), 5u) << lines[i];
    ASSERT_TRUE(id.contains(f[0])) << f[0];
    if (id[f[0]].is_null()) {
      EXPECT_EQ(f[1], "");
    } else {
      EXPECT_EQ(std::stod(f[1]), id[f[0]].get<double>()) << f[0];
    }
    if (id.contains(f[0] + "_ci95")) {
      EXPECT_EQ(std::stod(f[3]), id[f[0] + "_ci95"][0].get<double>()) << f[0];
      EXPECT_EQ(std::stod(f[4]), id[f[0] + "_ci95"][1].get<double>()) << f[0];
    } else {
      EXPECT_EQ(f[3] + f[4], "") << f[0];
    }
    units[f[0]] = f[2];
  }
  EXPECT_EQ(units["m_kg"], "kg");
  EXPECT_EQ(units["c_kg_s"], "kg/s");
  EXPECT_EQ(units["k_N_m"], "N/m");
  EXPECT_EQ(units["Kt1_N_m2"], "N/m^2");
  EXPECT_EQ(units["fn_hz"], "Hz");
  EXPECT_EQ(units["zeta"], "-");
}

// sifs-tap tests write their FRF (sensor N per hammer N) the same way.
TEST(ReportFiles, SifsTapFrfFiles) {
  TempDir d;
  const fs::path spec = d.write("spec.yaml",
                                "format: chatterlab-synth/1\nname: sifs-files\nseed: 5\n"
                                "tool: {teeth: 4, radius_mm: 9.525, helix_deg: 30}\nsifs: {}\n");
  const fs::path campaign = d.path() / "campaign";
  const fs::path out = d.path() / "report";
  synthesize_campaign(spec, campaign);
  std::ostringstream log;
  ReportOptions opt;
  opt.pdf = false;
  opt.jobs = 2;
  ASSERT_EQ(run_report(campaign, out, opt, log), 0) << log.str();
  std::ifstream rin(out / "results.json");
  const json r = json::parse(rin);
  int taps = 0;
  for (const auto& [id, t] : r["tests"].items()) {
    if (t["kind"] != "sifs-tap" || t["status"] != "ok") continue;
    ++taps;
    // results.json names both files and the figure's data.
    ASSERT_EQ(t["frf_csv"], id + "/frf.csv");
    ASSERT_EQ(t["frf_uff"], id + "/frf.uff");
    EXPECT_TRUE(fs::exists(out / t["figures"]["frf"]["csv"].get<std::string>()));
    const auto lines = lines_of(out / id / "frf.csv");
    ASSERT_GE(lines.size(), 10u) << id;
    EXPECT_EQ(lines[2], "f_hz,re,im,coherence,fit_re,fit_im") << id;
    const auto functions = uff::read_uff58(out / id / "frf.uff");
    ASSERT_EQ(functions.size(), 3u) << id;  // H1, fit, coherence
    EXPECT_EQ(functions[0].function_type, uff::kFrf);
    EXPECT_EQ(functions[1].id1, "fit " + id);
    EXPECT_EQ(functions[2].function_type, uff::kCoherence);
    EXPECT_EQ(static_cast<std::size_t>(functions[0].samples()), lines.size() - 3);
    const auto table = frf_text::read_frf_text(out / id / "frf.csv", id);
    EXPECT_EQ(table.f_hz.size(), functions[0].samples());
  }
  EXPECT_GE(taps, 2);
  expect_every_figure_file_named(r, out);
}

// A figure that cannot be drawn keeps its data file, and only that file is named; a drawn
// figure names its SVG, PNG and CSV.
TEST(ReportFiles, FigureFilesNameOnlyWhatWasWritten) {
  render::Figure good;
  good.panels.emplace_back().series.push_back({{1.0, 2.0}, {3.0, 4.0}, "line"});
  render::Figure bad = good;
  bad.font_pt = 100;  // refused by the renderer, not by the CSV writer
  FigureJobs jobs;
  jobs.add("tap/x", "good", "figures/t-good", good);
  jobs.add("tap/x", "bad", "figures/t-bad", bad);
  jobs.add("group:g", "only", "figures/g-only", good);
  TempDir d;
  const FigureSet set = jobs.draw(d.path(), 2);
  ASSERT_EQ(set.errors.size(), 1u);
  EXPECT_NE(set.errors[0].find("figures/t-bad"), std::string::npos) << set.errors[0];
  const json t = figure_files_json(set, "tap/x");
  EXPECT_EQ(t, json({{"good",
                      {{"svg", "figures/t-good.svg"},
                       {"png", "figures/t-good.png"},
                       {"csv", "figures/t-good.csv"}}},
                     {"bad", {{"csv", "figures/t-bad.csv"}}}}));
  EXPECT_TRUE(fs::exists(d.path() / "figures/t-bad.csv"));
  EXPECT_FALSE(fs::exists(d.path() / "figures/t-bad.png"));
  EXPECT_EQ(figure_files_json(set, "group:g")["only"].size(), 3u);
  EXPECT_EQ(figure_files_json(set, "tap/y"), json::object());
}

}  // namespace
}  // namespace chatterlab::app
