#include "app/report_figures.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>

#include "app/dynamics_figures.h"
#include "app/format.h"
#include "app/parallel.h"
#include "render/gnuplot_backend.h"
#include "render/render_error.h"

namespace chatterlab::app {
namespace {

constexpr double kRadToDeg = 57.29577951308232;
// Between a test id and a figure kind in a job name (a character no folder name holds).
constexpr char kKindSeparator = '\x1f';

// Appends a phase sample, breaking the line (NaN) where it wraps between +180 and -180 deg
// so that a wrap draws no vertical stroke across the panel.
void push_phase(render::Series& s, double f, double deg) {
  if (!s.y.empty() && std::isfinite(s.y.back()) && std::isfinite(deg) &&
      std::abs(deg - s.y.back()) > 180.0) {
    s.x.push_back(f);
    s.y.push_back(std::nan(""));
  }
  s.x.push_back(f);
  s.y.push_back(deg);
}

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

std::string file_stem(const std::string& id) {
  std::string s = id.empty() ? "root" : id;
  std::replace(s.begin(), s.end(), '/', '-');
  return s;
}

}  // namespace

render::Figure tap_frf_figure(const TestOutcome& t) {
  const TapOutcome& tap = *t.tap;
  // Shown range: around the fit band (or the whole FRF when no fit), within the FRF's range.
  double lo = tap.f_hz.size() ? tap.f_hz[0] : 1.0;
  double hi = tap.f_hz.size() ? tap.f_hz[tap.f_hz.size() - 1] : 2.0;
  if (std::isfinite(tap.band_lo_hz) && std::isfinite(tap.band_hi_hz)) {
    lo = std::max(lo, tap.band_lo_hz / 1.5);
    hi = std::min(hi, tap.band_hi_hz * 1.5);
  }
  render::Series mag1, mag2, fit_mag, ph1, fit_ph, coh;
  mag1.label = "H1";
  mag2.label = "H2";
  mag2.style = render::SeriesStyle::kDashedLine;
  fit_mag.label = "fit";
  fit_mag.style = render::SeriesStyle::kDashedLine;
  ph1.label = "H1";
  fit_ph.label = "fit";
  fit_ph.style = render::SeriesStyle::kDashedLine;
  coh.label = "coherence";
  for (Eigen::Index i = 0; i < tap.f_hz.size(); ++i) {
    const double f = tap.f_hz[i];
    if (f < lo || f > hi) continue;
    mag1.x.push_back(f);
    mag1.y.push_back(std::abs(tap.h1[i]));
    mag2.x.push_back(f);
    mag2.y.push_back(std::abs(tap.h2[i]));
    push_phase(ph1, f, std::arg(tap.h1[i]) * kRadToDeg);
    coh.x.push_back(f);
    coh.y.push_back(tap.coherence[i]);
    if (tap.fit_ok && tap.fitted.size() == tap.f_hz.size()) {
      const bool in_band = f >= tap.band_lo_hz && f <= tap.band_hi_hz;
      fit_mag.x.push_back(f);
      fit_mag.y.push_back(in_band ? std::abs(tap.fitted[i]) : std::nan(""));
      push_phase(fit_ph, f, in_band ? std::arg(tap.fitted[i]) * kRadToDeg : std::nan(""));
    }
  }
  mag1.color = ph1.color = "#0072B2";
  mag2.color = "#56B4E9";
  fit_mag.color = fit_ph.color = "#D55E00";
  coh.color = "#009E73";
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = 5.4;
  render::Axes& a = fig.panels.emplace_back();
  a.y_label = "|receptance| [m/N]";
  a.log_x = a.log_y = true;
  a.relative_height = 2.2;
  a.series = {mag1, mag2};
  if (!fit_mag.x.empty()) a.series.push_back(fit_mag);
  render::Axes& p = fig.panels.emplace_back();
  p.y_label = "phase [deg]";
  p.log_x = true;
  p.y_range = render::Range{-180, 180};
  p.relative_height = 1.2;
  p.series = {ph1};
  if (!fit_ph.x.empty()) p.series.push_back(fit_ph);
  p.legend = render::LegendPosition::kNone;
  render::Axes& c = fig.panels.emplace_back();
  c.x_label = "frequency [Hz]";
  c.y_label = "coherence [-]";
  c.log_x = true;
  c.y_range = render::Range{0, 1.05};
  c.relative_height = 1.0;
  c.series = {coh};
  c.legend = render::LegendPosition::kNone;
  // Not through a, p, c: emplace_back may have moved the earlier panels.
  for (auto& ax : fig.panels) ax.x_range = render::Range{lo, hi};
  return fig;
}

render::Figure dyno_force_figure(const CampaignResults& r) {
  const auto& g = *r.dyno_group;
  // Per unit depth when the records' depths differ, else in newtons at the common depth.
  double depth = -1;
  bool same_depth = true;
  for (const auto& t : r.tests) {
    if (!t.dyno) continue;
    if (depth < 0) depth = t.dyno->axial_depth_m;
    same_depth = same_depth && std::abs(t.dyno->axial_depth_m - depth) < 1e-12;
  }
  const double scale_depth = same_depth ? depth : 1e-3;  // N, or N per mm of depth
  render::Series ft, fr, lt, lr;
  ft.label = "tangential, measured";
  fr.label = "radial, measured";
  ft.style = fr.style = render::SeriesStyle::kPoints;
  lt.label = "tangential, fit";
  lr.label = "radial, fit";
  ft.color = lt.color = "#0072B2";
  fr.color = lr.color = "#D55E00";
  lt.style = lr.style = render::SeriesStyle::kDashedLine;
  double hmax = 0;
  for (const auto& t : r.tests) {
    if (!t.dyno) continue;
    const double h_mm = t.dyno->feed_per_tooth_m * 1e3;
    const double s = scale_depth / t.dyno->axial_depth_m;
    ft.x.push_back(h_mm);
    ft.y.push_back(t.dyno->result.mean_Ft_N * s);
    fr.x.push_back(h_mm);
    fr.y.push_back(t.dyno->result.mean_Fr_N * s);
    hmax = std::max(hmax, h_mm);
  }
  for (int i = 0; i <= 20; ++i) {
    const double h_mm = hmax * 1.1 * i / 20.0;
    lt.x.push_back(h_mm);
    lt.y.push_back(g.fit.tangential.force_N(h_mm * 1e-3, scale_depth));
    lr.x.push_back(h_mm);
    lr.y.push_back(g.fit.radial.force_N(h_mm * 1e-3, scale_depth));
  }
  render::Figure fig;
  fig.height_in = 3.4;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "feed per tooth [mm]";
  a.y_label = same_depth ? "average force magnitude [N]" : "average force per depth [N/mm]";
  a.x_range = render::Range{0, hmax * 1.1};
  a.legend = render::LegendPosition::kTopLeft;
  a.series = {ft, fr, lt, lr};
  return fig;
}

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
  for (const auto& rr : v.repeat.runs) seeded += rr.summary.ok ? 1 : 0;
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
    // Repeatability runs first (drawn behind), light; labelled once.
    for (const auto& rr : v.repeat.runs) {
      const Eigen::Index rc = history_column(rr.history, est.key);
      if (!rr.summary.ok || rc < 0) continue;
      render::Series s = percent_series(rr.history, rc, r0);
      s.color = "#A9CCE3";
      if (first && a.series.empty()) s.label = std::to_string(seeded) + " seeded starts";
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

FigureSet render_report_figures(const CampaignResults& r, const std::filesystem::path& out,
                                int jobs) {
  FigureSet set;
  struct Job {
    std::string id;  // empty: the dyno figure
    std::string rel;
    render::Figure fig;
  };
  std::vector<Job> work;
  for (const auto& t : r.tests) {
    if (t.status.ok && t.tap && t.tap->f_hz.size() > 1) {
      work.push_back(
          {t.spec->id, "figures/tap-" + file_stem(t.spec->id) + "-frf", tap_frf_figure(t)});
    }
  }
  if (r.dyno_group && r.dyno_group->summary.ok) {
    work.push_back({"", "figures/dyno-force-vs-feed", dyno_force_figure(r)});
  }
  for (const auto& t : r.tests) {
    if (!t.status.ok || !t.cut) continue;
    const auto& c = *t.cut;
    const std::string stem = "figures/cut-" + file_stem(t.spec->id) + "-";
    work.push_back({t.spec->id + kKindSeparator + "processing", stem + "processing",
                    cut_processing_figure(c)});
    if (c.offset_status.ok) {
      work.push_back(
          {t.spec->id + kKindSeparator + "offset", stem + "offset", cut_offset_figure(c.offset)});
    }
    if (c.ramped && c.bifurcation_status.ok) {
      work.push_back({t.spec->id + kKindSeparator + "bifurcation", stem + "bifurcation",
                      bifurcation_figure(c.depth_n_m, {{"x", c.x_n_m}},
                                         c.bifurcation.bifurcation_depth_m, false)});
      if (!c.poincare.empty()) {
        work.push_back({t.spec->id + kKindSeparator + "poincare", stem + "poincare",
                        poincare_figure(c.poincare)});
      }
    }
    const CutEstimation& e = c.estimation;
    if (e.summary.ok) {
      const auto reference = reference_values(r, t);
      for (const auto& v : e.variants) {
        if (!v.run.summary.ok || v.run.history.time_s.size() < 2) continue;
        work.push_back({t.spec->id + kKindSeparator + "estimator:" + v.run.estimator,
                        stem + v.run.estimator, estimator_error_figure(v, reference)});
      }
      if (e.chip_t_s.size() > 1 && e.chip_m.rows() == e.chip_t_s.size()) {
        work.push_back(
            {t.spec->id + kKindSeparator + "chip", stem + "chip", chip_thickness_figure(e)});
      }
    }
  }
  std::vector<std::string> errors(work.size());
  parallel_for(work.size(), jobs, [&](std::size_t i) {
    try {
      render::render_report_figure(work[i].fig, out / work[i].rel);
    } catch (const std::exception& e) {
      errors[i] = "figure " + work[i].rel + " not drawn: " + e.what();
    }
  });
  for (std::size_t i = 0; i < work.size(); ++i) {
    if (!errors[i].empty()) {
      set.errors.push_back(errors[i]);
      continue;
    }
    const auto hash = work[i].id.find(kKindSeparator);
    if (hash != std::string::npos) {
      set.cut[work[i].id.substr(0, hash)][work[i].id.substr(hash + 1)] = work[i].rel;
    } else if (work[i].id.empty() && work[i].rel.find("dyno") != std::string::npos) {
      set.dyno = work[i].rel;
    } else {
      set.tap[work[i].id] = work[i].rel;
    }
  }
  return set;
}

}  // namespace chatterlab::app
