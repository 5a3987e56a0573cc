#include "app/report/figure_jobs.h"

#include <algorithm>

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

FigureSet FigureJobs::draw(const std::filesystem::path& out, int jobs) const {
  std::vector<std::string> errors(jobs_.size());
  parallel_for(jobs_.size(), jobs, [&](std::size_t i) {
    try {
      render::render_report_figure(jobs_[i].figure, out / jobs_[i].stem);
    } catch (const std::exception& e) {
      errors[i] = "figure " + jobs_[i].stem + " not drawn: " + e.what();
    }
  });
  FigureSet set;
  for (std::size_t i = 0; i < jobs_.size(); ++i) {
    if (errors[i].empty()) {
      set.stems[jobs_[i].owner][jobs_[i].key] = jobs_[i].stem;
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
