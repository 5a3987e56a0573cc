// The report's figures as jobs: each kind adds the figure models of its tests and groups,
// the report draws them all in parallel through render/ (gnuplot backend), and the kinds'
// report sections look their files up by owner and key.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "render/figure.h"

namespace chatterlab::app {

struct FigureSet {
  // owner (test id, or "group:<name>") -> figure key -> stem relative to the report folder
  // (stem.svg on screen, stem.png in print). A figure that could not be drawn is absent.
  std::map<std::string, std::map<std::string, std::string>> stems;
  // owner -> figure key -> the figure's data file relative to the report folder
  // ("figures/<stem>.csv", write_figure_csv), written whether or not the figure could be drawn.
  std::map<std::string, std::map<std::string, std::string>> data;
  std::vector<std::string> errors;  // figures that could not be drawn (or their data written)

  // The stem of figure `key` of `owner`; empty when it was not drawn.
  std::string of(const std::string& owner, const std::string& key) const;
};

class FigureJobs {
 public:
  // Figure `key` of `owner`, written to <report>/<stem>.svg and .png, its data to <stem>.csv.
  void add(const std::string& owner, const std::string& key, const std::string& stem,
           render::Figure figure);
  std::size_t size() const { return jobs_.size(); }

  // Draws every figure on up to `jobs` threads; a figure that fails is listed in errors.
  FigureSet draw(const std::filesystem::path& out, int jobs) const;

 private:
  struct Job {
    std::string owner, key, stem;
    render::Figure figure;
  };
  std::vector<Job> jobs_;
};

// The data behind a figure as CSV (docs/format/results-json.md, "Figure data"), long format:
//   # chatterlab figure data: <title>
//   # panel 1: x = <x label> (log), y = <y label> (log)       one line per panel
//   panel,series,x,y
//   1,H1,100,1.5e-06                                          one row per point, in order
// `panel` is 1-based from the top; `series` is the legend text ("series <n>", 1-based in its
// panel, when it has none; quoted when it holds a comma or a quote); every point of the series
// as the figure model holds it (before any reduction for drawing), 9 significant digits at
// most (%.9g: every float exactly, a double to 5e-9 relative); an empty x or y is NaN or
// infinite (a break in the line). Throws InputError when it cannot write.
void write_figure_csv(const render::Figure& figure, const std::filesystem::path& file,
                      const std::string& title);

// The stems to draw `stems` (in order) to: each as it is, but a stem already used by an earlier
// one gets "-2", "-3", ... (the first number that no figure uses), so that no two figures share
// a file.
std::vector<std::string> unique_figure_stems(const std::vector<std::string>& stems);

// "figures/<prefix>-<id with / as ->-": the stem prefix of a test's figures ("root" for the
// campaign root's test).
std::string figure_stem(const std::string& prefix, const std::string& id);

}  // namespace chatterlab::app
