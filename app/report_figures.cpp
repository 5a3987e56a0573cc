#include "app/report_figures.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>

#include "app/parallel.h"
#include "render/gnuplot_backend.h"
#include "render/render_error.h"

namespace chatterlab::app {
namespace {

constexpr double kRadToDeg = 57.29577951308232;

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
    if (work[i].id.empty() && work[i].rel.find("dyno") != std::string::npos) {
      set.dyno = work[i].rel;
    } else {
      set.tap[work[i].id] = work[i].rel;
    }
  }
  return set;
}

}  // namespace chatterlab::app
