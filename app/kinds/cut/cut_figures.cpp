// Figures of a cut test (000 figs 5.9-5.14, 6.1-6.20): processing, offset search, measured
// bifurcation and Poincare maps, estimator percent error, chip thickness.
#include <algorithm>
#include <cmath>

#include "analysis/common/constants.h"
#include "app/core/format.h"
#include "app/kinds/cut/cut_kind.h"
#include "app/report/dynamics_figures.h"
#include "app/report/figure_jobs.h"

namespace chatterlab::app {
namespace {

// "m_kg" -> "m [kg]", "Kt1_N_m2" -> "Kt1 [N/m^2]" (EXPERIMENT_FORMAT.md estimate keys).
std::string key_label(const std::string& key) {
  const auto u = key.find('_');
  if (u == std::string::npos) return key;
  std::string unit = key.substr(u + 1);
  if (unit.size() > 1 && unit.back() == '2') unit.insert(unit.size() - 1, "^");
  std::replace(unit.begin(), unit.end(), '_', '/');
  return key.substr(0, u) + " [" + unit + "]";
}

// Column of `key` in a history; -1 when absent.
Eigen::Index history_column(const estimate::EstimateHistory& h, const std::string& key) {
  const auto it = std::find(h.columns.begin(), h.columns.end(), key);
  return it == h.columns.end() ? -1 : static_cast<Eigen::Index>(it - h.columns.begin());
}

// 100 (value - reference) / |reference| of one history column against time.
render::Series percent_series(const estimate::EstimateHistory& h, Eigen::Index col,
                              double reference) {
  render::Series s;
  s.x.resize(static_cast<std::size_t>(h.time_s.size()));
  s.y.resize(s.x.size());
  for (Eigen::Index i = 0; i < h.time_s.size(); ++i) {
    s.x[static_cast<std::size_t>(i)] = h.time_s[i];
    s.y[static_cast<std::size_t>(i)] = 100.0 * (h.values(i, col) - reference) / std::abs(reference);
  }
  return s;
}

// The q-quantile (0..1) of v by nearest rank; v is reordered. v must not be empty.
double quantile(std::vector<double>& v, double q) {
  const auto k = static_cast<std::ptrdiff_t>(std::lround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[static_cast<std::size_t>(k)];
}

}  // namespace

render::Figure cut_processing_figure(const CutOutcome& c) {
  render::Figure fig;
  fig.height_in = 4.8;
  render::Axes& k = fig.panels.emplace_back();
  k.title = "runout contour over " + std::to_string(c.air_revolutions) + " air revolutions";
  k.x_label = "tachometer phase [deg]";
  k.y_label = "at the sensor [um]";
  std::vector<double> ph, cx, cy;
  for (Eigen::Index i = 0; i < c.contour.phase_rad.size(); ++i) {
    ph.push_back(c.contour.phase_rad[i] * kRadToDeg);
    cx.push_back(c.contour.x_m[i] * 1e6);
    cy.push_back(c.contour.y_m[i] * 1e6);
  }
  k.series.emplace_back(ph, cx, "x");
  k.series.emplace_back(ph, cy, "y");
  k.x_range = render::Range{0, 360};
  render::Axes& d = fig.panels.emplace_back();
  d.title = "three revolutions of the cut";
  d.x_label = "time [s]";
  d.y_label = "x at the tip [um]";
  std::vector<double> t, raw, done;
  for (Eigen::Index i = 0; i < c.excerpt_t_s.size(); ++i) {
    t.push_back(c.excerpt_t_s[i]);
    raw.push_back(c.excerpt_raw_x_m[i] * 1e6);
    done.push_back(c.excerpt_x_m[i] * 1e6);
  }
  // The raw signal carries the sensor's gap offset: shown about its own mean.
  double mean = 0;
  for (double v : raw) mean += v / static_cast<double>(raw.size());
  for (double& v : raw) v -= mean;
  d.series.emplace_back(t, raw, "raw (sensor x sensor_to_tip, mean removed)",
                        render::SeriesStyle::kLine, "#999999");
  d.series.emplace_back(t, done, "processed (contour removed)", render::SeriesStyle::kLine,
                        "#0072B2");
  return fig;
}

render::Figure cut_offset_figure(const sync::OffsetAngleResult& o) {
  render::Figure fig;
  fig.height_in = 4.8;
  render::Axes& e = fig.panels.emplace_back();
  e.x_label = "offset angle [deg]";
  e.y_label = "RMS difference [um]";
  std::vector<double> a, err;
  for (Eigen::Index i = 0; i < o.search.candidate_deg.size(); ++i) {
    a.push_back(o.search.candidate_deg[i]);
    err.push_back(o.search.error_m[i] * 1e6);
  }
  e.series.emplace_back(a, err, "simulated vs measured revolution");
  e.x_range = render::Range{0, 360};
  e.legend = render::LegendPosition::kNone;
  render::Axes& r = fig.panels.emplace_back();
  r.x_label = "tool angle theta_1 [deg]";
  r.y_label = "tip deflection [um]";
  std::vector<double> th, mx, my, sx, sy;
  for (Eigen::Index i = 0; i < o.theta1_deg.size(); ++i) {
    th.push_back(o.theta1_deg[i]);
    mx.push_back(o.measured_x_m[i] * 1e6);
    my.push_back(o.measured_y_m[i] * 1e6);
    sx.push_back(o.simulated_x_m[i] * 1e6);
    sy.push_back(o.simulated_y_m[i] * 1e6);
  }
  r.series.emplace_back(th, mx, "x measured", render::SeriesStyle::kLine, "#0072B2");
  r.series.emplace_back(th, sx, "x simulated", render::SeriesStyle::kDashedLine, "#0072B2");
  r.series.emplace_back(th, my, "y measured", render::SeriesStyle::kLine, "#D55E00");
  r.series.emplace_back(th, sy, "y simulated", render::SeriesStyle::kDashedLine, "#D55E00");
  r.x_range = render::Range{0, 360};
  r.legend = render::LegendPosition::kOutsideRight;
  return fig;
}

// 000 figs 6.1-6.17 (one variant's estimates against time) and 6.19-6.20 (seeded starts).
render::Figure estimator_error_figure(const VariantOutcome& v,
                                      const std::map<std::string, ReferenceValue>& reference) {
  const estimate::EkfResult& run = v.run;
  // "hammer test (m ..., c ...)" -> "hammer test": where the run started.
  const std::string start = v.start.substr(0, v.start.find(" ("));
  int seeded = 0;
  for (const auto& rr : v.repeat.runs) seeded += rr.summary.ok() ? 1 : 0;
  render::Figure fig;
  fig.share_x = true;
  double t_lo = 0.0, t_hi = 1.0;
  if (run.history.time_s.size() > 1) {
    t_lo = run.history.time_s[0];
    t_hi = run.history.time_s[run.history.time_s.size() - 1];
  }
  for (const auto& est : run.estimates) {
    const Eigen::Index col = history_column(run.history, est.key);
    if (col < 0 || run.history.time_s.size() < 2) continue;
    const auto ref = reference.find(est.key);
    const bool has_ref =
        ref != reference.end() && std::isfinite(ref->second.value) && ref->second.value != 0.0;
    // Without a reference: the difference from the run's own final value.
    const double r0 = has_ref ? ref->second.value : est.value;
    if (!std::isfinite(r0) || r0 == 0.0) continue;
    const bool first = fig.panels.empty();
    render::Axes& a = fig.panels.emplace_back();
    const std::string source = !has_ref                             ? std::string()
                               : ref->second.source == "identified" ? "the identified values"
                               : ref->second.source == "truth.yaml" ? "truth.yaml"
                                                                    : "the test.yaml reference";
    a.title = has_ref ? key_label(est.key) + " against " + source + " (" +
                            fmt_sig(ref->second.value, 4) + "), final " + fmt_sig(est.value, 4)
                      : key_label(est.key) + " against its own final value " +
                            fmt_sig(est.value, 4) + " (no reference)";
    a.y_label = has_ref ? "error [%]" : "difference [%]";
    a.legend = first ? render::LegendPosition::kAbove : render::LegendPosition::kNone;
    // Repeatability runs first (drawn behind), light; labelled once. Runs on one time grid
    // are drawn as their envelope, the lowest and the highest value of any run at each time
    // (two lines instead of one per run: the figure stays small on screen); otherwise each
    // run is drawn.
    std::vector<render::Series> runs;
    for (const auto& rr : v.repeat.runs) {
      const Eigen::Index rc = history_column(rr.history, est.key);
      if (!rr.summary.ok() || rc < 0) continue;
      runs.push_back(percent_series(rr.history, rc, r0));
    }
    const bool one_grid =
        runs.size() > 2 && std::all_of(runs.begin(), runs.end(), [&](const render::Series& s) {
          return s.x == runs.front().x;
        });
    if (one_grid) {
      render::Series lo = runs.front(), hi = runs.front();
      for (const auto& s : runs) {
        for (std::size_t i = 0; i < s.y.size(); ++i) {
          lo.y[i] = std::min(lo.y[i], s.y[i]);
          hi.y[i] = std::max(hi.y[i], s.y[i]);
        }
      }
      runs = {std::move(lo), std::move(hi)};
    }
    for (auto& s : runs) {
      s.color = "#A9CCE3";
      if (first && a.series.empty()) {
        s.label = one_grid ? "range of " + std::to_string(seeded) + " seeded starts"
                           : std::to_string(seeded) + " seeded starts";
      }
      a.series.push_back(std::move(s));
    }
    render::Series main = percent_series(run.history, col, r0);
    main.color = "#0072B2";
    if (first) main.label = "run from the " + start + " values";
    // y range (the first instants can reach +-1000 %): symmetric about 0, half-width the larger
    // of 5 % and 1.5 x the larger magnitude of the 2nd and 98th percentiles of every plotted
    // value over the second half of the run, where the filters have settled; the start-up
    // transient may leave it.
    std::vector<double> late;
    const double t_mid = 0.5 * (t_lo + t_hi);
    const auto collect = [&](const render::Series& s) {
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (s.x[i] >= t_mid && std::isfinite(s.y[i])) late.push_back(s.y[i]);
      }
    };
    collect(main);
    for (const auto& s : a.series) collect(s);
    double half = 5.0;
    if (!late.empty()) {
      const double lo = quantile(late, 0.02), hi = quantile(late, 0.98);
      half = std::max(half, 1.5 * std::max(std::abs(lo), std::abs(hi)));
    }
    a.y_range = render::Range{-half, half};
    a.series.emplace_back(std::vector<double>{t_lo, t_hi}, std::vector<double>{0.0, 0.0},
                          std::string(), render::SeriesStyle::kDashedLine, "#606060");
    a.series.push_back(std::move(main));
  }
  if (fig.panels.empty()) {
    render::Axes& a = fig.panels.emplace_back();
    a.title = run.estimator + ": no estimate history";
  }
  fig.panels.back().x_label = "time from the window start [s]";
  for (auto& a : fig.panels) a.x_range = render::Range{t_lo, t_hi};
  fig.height_in = 1.0 + 1.55 * static_cast<double>(fig.panels.size());  // legend above
  return fig;
}

// 000 fig. 6.18: time from the window start, as the estimator figures.
render::Figure chip_thickness_figure(const CutEstimation& e) {
  render::Figure fig;
  fig.height_in = 2.8;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "time from the window start [ms]";
  a.y_label = "chip thickness [um]";
  std::vector<double> t(static_cast<std::size_t>(e.chip_t_s.size()));
  for (Eigen::Index i = 0; i < e.chip_t_s.size(); ++i) {
    t[static_cast<std::size_t>(i)] = (e.chip_t_s[i] - e.window.start_s) * 1e3;
  }
  for (Eigen::Index p = 0; p < e.chip_m.cols(); ++p) {
    std::vector<double> h(t.size());
    for (Eigen::Index i = 0; i < e.chip_m.rows(); ++i) {
      h[static_cast<std::size_t>(i)] = e.chip_m(i, p) * 1e6;
    }
    a.series.emplace_back(t, std::move(h), "tooth " + std::to_string(p + 1));
  }
  if (!t.empty()) a.x_range = render::Range{t.front(), t.back()};
  return fig;
}

void CutKind::figures(const CampaignResults& r, const TestOutcome& t, FigureJobs& jobs) const {
  const CutOutcome& c = t.result_of<CutOutcome>();
  const std::string& id = t.spec->id;
  const std::string stem = figure_stem("cut", id);
  jobs.add(id, "processing", stem + "processing", cut_processing_figure(c));
  if (c.offset_status.ok()) jobs.add(id, "offset", stem + "offset", cut_offset_figure(c.offset));
  if (c.ramped && c.bifurcation_status.ok()) {
    jobs.add(id, "bifurcation", stem + "bifurcation",
             bifurcation_figure(c.depth_n_m, {{"x", c.x_n_m}}, c.bifurcation.bifurcation_depth_m,
                                false));
    if (!c.poincare.empty())
      jobs.add(id, "poincare", stem + "poincare", poincare_figure(c.poincare));
  }
  if (!c.ramped && c.orbit_status.ok() && !c.poincare.empty()) {
    jobs.add(id, "poincare", stem + "poincare", poincare_figure(c.poincare));
  }
  const CutEstimation& e = c.estimation;
  if (!e.summary.ok()) return;
  const auto reference = reference_values(r, t);
  for (const auto& v : e.variants) {
    if (!v.run.summary.ok() || v.run.history.time_s.size() < 2) continue;
    jobs.add(id, "estimator:" + v.run.estimator, stem + v.run.estimator,
             estimator_error_figure(v, reference));
  }
  if (e.chip_t_s.size() > 1 && e.chip_m.rows() == e.chip_t_s.size()) {
    jobs.add(id, "chip", stem + "chip", chip_thickness_figure(e));
  }
}

}  // namespace chatterlab::app
