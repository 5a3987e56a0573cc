// The report of a grinding test (002 figs 3-4): the four estimators compared in a table, the
// wheel diameter against cycle with 3-sigma bands, the inspections and the truth, and R0 and
// R_a predicted against measured for the xr ids. Every number shown is in results.json
// (GrindingKind::results).
#include <cmath>

#include "analysis/kalman/chi_square.h"
#include "app/core/format.h"
#include "app/kinds/grinding/grinding_kind.h"
#include "app/report/figure_jobs.h"

namespace chatterlab::app {

using nlohmann::json;
namespace g = chatterlab::grinding;

namespace {

constexpr std::array<const char*, 4> kEstimatorColours = {"#0072B2", "#D55E00", "#009E73",
                                                          "#CC79A7"};

std::vector<double> cycles_of(const GrindingResult& res) {
  std::vector<double> c;
  for (int i = 1; i <= res.cycles; ++i) c.push_back(i);
  return c;
}

// One state of an estimator per cycle, scaled, plus k times its 3sigma (k = 0: the value).
std::vector<double> per_cycle(const g::GrindingRun& run, int state, double scale, double k,
                              double offset = 0.0) {
  std::vector<double> v;
  for (const auto& c : run.per_cycle) {
    v.push_back((c.posterior.x[state] + k * c.posterior.three_sigma[state]) * scale - offset);
  }
  return v;
}

// A value and its band as three series of one colour: value solid, bands dashed, unlabelled.
void add_banded(render::Axes& a, const std::vector<double>& x, const std::vector<double>& v,
                const std::vector<double>& lo, const std::vector<double>& hi,
                const std::string& label, const std::string& colour) {
  a.series.emplace_back(x, v, label, render::SeriesStyle::kLinePoints, colour);
  a.series.emplace_back(x, lo, "", render::SeriesStyle::kDashedLine, colour);
  a.series.emplace_back(x, hi, "", render::SeriesStyle::kDashedLine, colour);
}

// The inspections that measured `field` (d_s or R_a): cycles and values.
std::pair<std::vector<double>, std::vector<double>> inspected(const GrindingResult& res,
                                                              double g::Inspection::*field) {
  std::pair<std::vector<double>, std::vector<double>> p;
  for (const auto& i : res.inspections) {
    if (!std::isfinite(i.*field)) continue;
    p.first.push_back(i.cycle);
    p.second.push_back(i.*field);
  }
  return p;
}

std::string value_or_na(double v, int digits) {
  return std::isfinite(v) ? fmt_sig(v, digits) : "n/a";
}

}  // namespace

render::Figure grinding_ds_figure(const GrindingResult& res) {
  const std::vector<double> x = cycles_of(res);
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = 5.4;
  render::Axes& a = fig.panels.emplace_back();
  a.y_label = "wheel diameter d_s [mm]";
  a.relative_height = 1.4;
  render::Axes& b = fig.panels.emplace_back();
  b.x_label = "cycle";
  // With truth: the error against it and its 3-sigma band; without: the band's half-width.
  b.y_label = res.has_truth ? "d_s - truth [um]" : "3-sigma of d_s [um]";
  for (std::size_t k = 0; k < res.estimators.size(); ++k) {
    const auto& run = res.estimators[k].run;
    if (!run.summary.ok()) continue;
    const std::string name = g::kGrindingEstimators[k].name;
    fig.panels[0].series.emplace_back(x, per_cycle(run, g::kDs, 1.0, 0.0), name,
                                      render::SeriesStyle::kLine, kEstimatorColours[k]);
    if (res.has_truth) {
      std::vector<double> e, lo, hi;
      for (std::size_t i = 0; i < run.per_cycle.size(); ++i) {
        const auto& c = run.per_cycle[i];
        const double err =
            (c.posterior.x[g::kDs] - res.truth(static_cast<Eigen::Index>(i), g::kDs)) * 1e3;
        const double s3 = c.posterior.three_sigma[g::kDs] * 1e3;
        e.push_back(err);
        lo.push_back(err - s3);
        hi.push_back(err + s3);
      }
      add_banded(fig.panels[1], x, e, lo, hi, name, kEstimatorColours[k]);
    } else {
      std::vector<double> s3;
      for (const auto& c : run.per_cycle) s3.push_back(c.posterior.three_sigma[g::kDs] * 1e3);
      fig.panels[1].series.emplace_back(x, s3, name, render::SeriesStyle::kLinePoints,
                                        kEstimatorColours[k]);
    }
  }
  const auto [ix, iy] = inspected(res, &g::Inspection::ds_mm);
  if (!ix.empty()) {
    fig.panels[0].series.emplace_back(ix, iy, "inspection", render::SeriesStyle::kPoints,
                                      "#000000");
  }
  if (res.has_truth) {
    std::vector<double> t;
    for (Eigen::Index i = 0; i < res.truth.rows(); ++i) t.push_back(res.truth(i, g::kDs));
    fig.panels[0].series.emplace_back(x, t, "truth", render::SeriesStyle::kDashedLine, "#000000");
  }
  fig.panels[1].legend = render::LegendPosition::kNone;
  return fig;
}

render::Figure grinding_r0_figure(const GrindingResult& res) {
  const std::vector<double> x = cycles_of(res);
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = 5.0;
  render::Axes& a = fig.panels.emplace_back();
  a.y_label = "R0 [um]";
  render::Axes& b = fig.panels.emplace_back();
  b.x_label = "cycle";
  b.y_label = "R_a [um]";
  for (std::size_t k = 0; k < res.estimators.size(); ++k) {
    const auto& info = g::kGrindingEstimators[k];
    const auto& run = res.estimators[k].run;
    if (!info.estimates_R0 || !run.summary.ok()) continue;
    add_banded(fig.panels[0], x, per_cycle(run, g::kR0, 1.0, 0.0),
               per_cycle(run, g::kR0, 1.0, -1.0), per_cycle(run, g::kR0, 1.0, 1.0), info.name,
               kEstimatorColours[k]);
    std::vector<double> ra;
    for (const auto& c : run.per_cycle) ra.push_back(c.Ra_pred_um);
    fig.panels[1].series.emplace_back(x, ra, std::string(info.name) + " predicted",
                                      render::SeriesStyle::kLinePoints, kEstimatorColours[k]);
  }
  const auto [ix, iy] = inspected(res, &g::Inspection::Ra_um);
  if (!ix.empty()) {
    fig.panels[1].series.emplace_back(ix, iy, "measured", render::SeriesStyle::kPoints, "#000000");
  }
  if (res.has_truth) {
    std::vector<double> t;
    for (Eigen::Index i = 0; i < res.truth.rows(); ++i) t.push_back(res.truth(i, g::kR0));
    fig.panels[0].series.emplace_back(x, t, "truth", render::SeriesStyle::kDashedLine, "#000000");
  }
  return fig;
}

// Innovations (NIS per degree of freedom) per cycle: the mean over the cycle's updates without
// inspection values with the 95 % band of such a mean, and the update holding the cycle's
// inspection values with the 95 % band of one chi-square of its dimension.
render::Figure grinding_nis_figure(const GrindingResult& res) {
  const std::vector<double> x = cycles_of(res);
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = 4.6;
  render::Axes& a = fig.panels.emplace_back();
  a.y_label = "NIS / dof, fast";
  render::Axes& b = fig.panels.emplace_back();
  b.x_label = "cycle";
  b.y_label = "NIS / dof, inspection";
  bool band_fast = false;
  for (std::size_t k = 0; k < res.estimators.size(); ++k) {
    const auto& run = res.estimators[k].run;
    if (!run.summary.ok()) continue;
    const std::string name = g::kGrindingEstimators[k].name;
    std::vector<double> f, ix, iv, lo, hi, bx;
    for (const auto& c : run.per_cycle) {
      f.push_back(c.nis_fast_per_dof);
      if (c.nis_inspection_dof > 0) {
        ix.push_back(c.posterior.cycle);
        iv.push_back(c.nis_inspection_per_dof);
      }
    }
    fig.panels[0].series.emplace_back(x, f, name, render::SeriesStyle::kLinePoints,
                                      kEstimatorColours[k]);
    if (!ix.empty()) {
      fig.panels[1].series.emplace_back(ix, iv, name, render::SeriesStyle::kPoints,
                                        kEstimatorColours[k]);
    }
    if (!band_fast) {  // the fast updates have the same dimension for every id
      for (const auto& c : run.per_cycle) {
        if (c.nis_fast_dof <= 0) continue;
        const auto band = kalman::mean_chi_square_band(c.nis_fast_dof, 1);
        bx.push_back(c.posterior.cycle);
        lo.push_back(band.lower);
        hi.push_back(band.upper);
      }
      fig.panels[0].series.emplace_back(bx, lo, "95 % band", render::SeriesStyle::kDashedLine,
                                        "#000000");
      fig.panels[0].series.emplace_back(bx, hi, "", render::SeriesStyle::kDashedLine, "#000000");
      band_fast = true;
    }
  }
  // One chi-square per update: the band of the largest update (P, D_w, d_s, R_a) and of the
  // smallest (P, D_w, d_s) bracket every point's own band.
  for (int dof : {3, 4}) {
    const auto band = kalman::chi_square_band(dof);
    const std::vector<double> lo(x.size(), band.lower / dof), hi(x.size(), band.upper / dof);
    const std::string label = "95 % band, " + std::to_string(dof) + " dof";
    const std::string colour = dof == 3 ? "#555555" : "#999999";
    fig.panels[1].series.emplace_back(x, lo, label, render::SeriesStyle::kDashedLine, colour);
    fig.panels[1].series.emplace_back(x, hi, "", render::SeriesStyle::kDashedLine, colour);
  }
  return fig;
}

void GrindingKind::figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const {
  const GrindingResult& res = out.result_of<GrindingResult>();
  if (res.cycles < 1) return;
  const std::string stem = figure_stem("grinding", out.spec->id);
  jobs.add(out.spec->id, "ds", stem + "ds", grinding_ds_figure(res));
  jobs.add(out.spec->id, "r0", stem + "r0", grinding_r0_figure(res));
  jobs.add(out.spec->id, "nis", stem + "nis", grinding_nis_figure(res));
}

json GrindingKind::report_section(const CampaignResults&, const std::vector<const TestOutcome*>& ok,
                                  const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) {
    const GrindingResult& res = t->result_of<GrindingResult>();
    const GrindingSpec& s = t->spec->kind_spec<GrindingSpec>();
    json j;
    j["id"] = t->spec->id;
    j["cycles"] = res.cycles;
    int ds_measured = 0, ra_measured = 0, late = 0;
    for (const auto& i : res.inspections) {
      ds_measured += std::isfinite(i.ds_mm);
      ra_measured += std::isfinite(i.Ra_um);
      late += i.available_cycle > i.cycle;
    }
    j["ds_measured"] = ds_measured;
    j["ra_measured"] = ra_measured;
    j["late"] = late;
    std::string dressed;
    for (const auto& d : s.dressings) {
      dressed += (dressed.empty() ? "" : ", ") + std::string("before cycle ") +
                 std::to_string(d.before_cycle) + " (" + fmt_sig(d.depth_mm * 1e3, 3) + " um)";
    }
    j["has_dressings"] = !dressed.empty();
    j["dressings"] = dressed;
    j["has_truth"] = res.has_truth;
    json rows = json::array();
    for (std::size_t k = 0; k < res.estimators.size(); ++k) {
      const auto& info = g::kGrindingEstimators[k];
      const auto& e = res.estimators[k];
      json row;
      row["name"] = info.name;
      row["ok"] = e.run.summary.ok();
      row["message"] = e.run.summary.message;
      if (!e.run.summary.ok() || e.run.per_cycle.empty()) {
        rows.push_back(row);
        continue;
      }
      const auto& last = e.run.per_cycle.back().posterior;
      row["ds_mm"] = fmt_fixed(last.x[g::kDs], 5);
      row["ds_3sigma_um"] = fmt_sig(last.three_sigma[g::kDs] * 1e3, 3);
      const auto [rms, n] = prior_vs_inspection(e.run, res.inspections);
      row["ds_rms_insp_um"] = n ? fmt_sig(rms, 3) : "n/a";
      if (res.has_truth) {
        const Eigen::Index li = res.truth.rows() - 1;
        row["ds_err_truth_um"] = fmt_sig((last.x[g::kDs] - res.truth(li, g::kDs)) * 1e3, 3);
        row["R0_err_truth_um"] =
            info.estimates_R0 ? fmt_sig(last.x[g::kR0] - res.truth(li, g::kR0), 3) : "";
        row["nees"] = value_or_na(e.nees_per_dof, 3);
      }
      row["R0_um"] = info.estimates_R0 ? fmt_sig(last.x[g::kR0], 4) : "";
      row["R0_3sigma_um"] = info.estimates_R0 ? fmt_sig(last.three_sigma[g::kR0], 3) : "";
      row["nis_fast"] = value_or_na(e.run.nis_fast_per_dof(), 3);
      row["nis_end"] = value_or_na(e.run.nis_end_per_dof(), 3);
      row["steps_per_s"] =
          e.runtime_s > 0 ? fmt_sig(static_cast<double>(e.run.steps) / e.runtime_s, 3) : "n/a";
      // Rank r of n at the worst point, and at how many of the points the rank is full.
      row["observability"] = e.observability.ok
                                 ? std::to_string(e.observability.min_rank) + " of " +
                                       std::to_string(e.observability.states) + " (" +
                                       std::to_string(e.observability.full_rank_points) + "/" +
                                       std::to_string(e.observability.points) + " full)"
                                 : "n/a";
      rows.push_back(row);
    }
    j["estimators"] = rows;
    j["ds_figure"] = figures.of(t->spec->id, "ds");
    j["r0_figure"] = figures.of(t->spec->id, "r0");
    j["nis_figure"] = figures.of(t->spec->id, "nis");
    j["has_warnings"] = !t->warnings.empty();
    j["warnings"] = t->warnings;
    tests.push_back(j);
  }
  return {{"toc", json::array({{{"anchor", "grinding"}, {"title", "Grinding series"}}})},
          {"grinding_tests", tests}};
}

}  // namespace chatterlab::app
