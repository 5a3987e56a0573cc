#include "app/report/figure_jobs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>

#include "analysis/common/summary.h"
#include "app/core/checked_write.h"
#include "app/core/parallel.h"
#include "render/gnuplot_backend.h"

namespace chatterlab::app {

std::string FigureSet::of(const std::string& owner, const std::string& key) const {
  const auto it = stems.find(owner);
  if (it == stems.end()) return "";
  const auto k = it->second.find(key);
  return k == it->second.end() ? std::string() : k->second;
}

void FigureJobs::add(const std::string& owner, const std::string& key, const std::string& stem,
                     render::Figure figure) {
  jobs_.push_back({owner, key, stem, std::move(figure)});
}

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c == '\n' ? ' ' : c;
  }
  return q + "\"";
}

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

}  // namespace

void write_figure_csv(const render::Figure& figure, const std::filesystem::path& file,
                      const std::string& title) {
  std::ofstream out = open_for_writing(file);
  out << "# chatterlab figure data: " << one_line(title) << "\n";
  // With a shared x axis only the bottom panel carries the x label: it holds for every panel.
  std::string shared_x;
  if (figure.share_x && !figure.panels.empty()) shared_x = figure.panels.back().x_label;
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const render::Axes& a = figure.panels[p];
    const std::string x = a.x_label.empty() ? shared_x : a.x_label;
    out << "# panel " << p + 1 << ": x = " << one_line(x.empty() ? "-" : x)
        << (a.log_x ? " (log)" : "") << ", y = " << one_line(a.y_label.empty() ? "-" : a.y_label)
        << (a.log_y ? " (log)" : "");
    if (!a.title.empty()) out << ", title: " << one_line(a.title);
    out << "\n";
  }
  out << "panel,series,x,y\n";
  char buf[64];
  auto num = [&](double v) -> std::string {
    if (!std::isfinite(v)) return "";
    // 9 significant digits: the data is float-level (f32 signals, plotted values), a float
    // reads back exactly, and the demo's files are 31 % smaller than at 17
    // (docs/format/results-json.md, "Figure data").
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
  };
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const render::Axes& a = figure.panels[p];
    for (std::size_t k = 0; k < a.series.size(); ++k) {
      const render::Series& s = a.series[k];
      const std::string prefix =
          std::to_string(p + 1) + "," +
          csv_field(s.label.empty() ? "series " + std::to_string(k + 1) : s.label) + ",";
      if (!s.xf.empty() || !s.yf.empty()) {
        for (std::size_t i = 0; i < std::min(s.xf.size(), s.yf.size()); ++i) {
          const std::string xs = num(s.xf[i]);
          out << prefix << xs << ',' << num(s.yf[i]) << '\n';
        }
      } else {
        for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
          const std::string xs = num(s.x[i]);
          out << prefix << xs << ',' << num(s.y[i]) << '\n';
        }
      }
    }
  }
  close_checked(out, file);
}

std::vector<std::string> unique_figure_stems(const std::vector<std::string>& stems) {
  std::set<std::string> taken(stems.begin(), stems.end());
  std::set<std::string> used;
  std::vector<std::string> out;
  out.reserve(stems.size());
  for (const auto& stem : stems) {
    std::string s = stem;
    for (int n = 2; used.count(s) > 0; ++n) {
      s = stem + "-" + std::to_string(n);
      if (taken.count(s) > 0) s = stem;  // another figure's own stem: try the next number
    }
    used.insert(s);
    out.push_back(s);
  }
  return out;
}

FigureSet FigureJobs::draw(const std::filesystem::path& out, int jobs) const {
  std::vector<std::string> errors(jobs_.size());
  std::vector<std::string> data_errors(jobs_.size());
  // Two tests whose ids give the same stem ("a/b" and "a-b") must not share a file.
  std::vector<std::string> stems;
  for (const auto& j : jobs_) stems.push_back(j.stem);
  stems = unique_figure_stems(stems);
  // A message names a file by its place in the report: `out` is the temporary folder of the
  // run, gone once the report replaced --out.
  const std::string folder = out.string() + "/";
  const auto shown = [&](std::string m) {
    for (auto at = m.find(folder); at != std::string::npos; at = m.find(folder, at)) {
      m.erase(at, folder.size());
    }
    return m;
  };
  parallel_for(jobs_.size(), jobs, [&](std::size_t i) {
    try {
      const std::filesystem::path csv = out / (stems[i] + ".csv");
      std::filesystem::create_directories(csv.parent_path());
      write_figure_csv(jobs_[i].figure, csv, stems[i]);
    } catch (const std::exception& e) {
      data_errors[i] = "data of figure " + stems[i] + " not written: " + shown(e.what());
    }
    try {
      render::render_report_figure(jobs_[i].figure, out / stems[i]);
    } catch (const std::exception& e) {
      errors[i] = "figure " + stems[i] + " not drawn: " + shown(e.what());
    }
  });
  FigureSet set;
  for (std::size_t i = 0; i < jobs_.size(); ++i) {
    if (data_errors[i].empty()) {
      set.data[jobs_[i].owner][jobs_[i].key] = stems[i] + ".csv";
    } else {
      set.errors.push_back(data_errors[i]);
    }
    if (errors[i].empty()) {
      set.stems[jobs_[i].owner][jobs_[i].key] = stems[i];
    } else {
      set.errors.push_back(errors[i]);
    }
  }
  return set;
}

std::string figure_stem(const std::string& prefix, const std::string& id) {
  std::string s = id.empty() ? "root" : id;
  std::replace(s.begin(), s.end(), '/', '-');
  return "figures/" + prefix + "-" + s + "-";
}

}  // namespace chatterlab::app
