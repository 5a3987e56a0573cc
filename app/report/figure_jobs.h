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
  std::vector<std::string> errors;  // figures that could not be drawn

  // The stem of figure `key` of `owner`; empty when it was not drawn.
  std::string of(const std::string& owner, const std::string& key) const;
};

class FigureJobs {
 public:
  // Figure `key` of `owner`, written to <report>/<stem>.svg and .png.
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

// "figures/<prefix>-<id with / as ->-": the stem prefix of a test's figures ("root" for the
// campaign root's test).
std::string figure_stem(const std::string& prefix, const std::string& id);

}  // namespace chatterlab::app
