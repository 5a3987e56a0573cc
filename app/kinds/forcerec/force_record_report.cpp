// Figures, report section and truth comparison of the force-record kind (format section 4,
// docs/forcerec.md section 3).
#include <algorithm>
#include <cmath>

#include "app/core/format.h"
#include "app/core/vectors.h"
#include "app/kinds/forcerec/forcerec_kinds.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

constexpr const char* kMethodColours[3] = {"#D55E00", "#009E73", "#0072B2"};  // akf, smo, rd
constexpr const char* kNames[3] = {"AKF", "SMO", "RD"};
constexpr int kTimePeriods = 4;  // tooth periods in the time figure

std::string pct(double v) { return std::isfinite(v) ? fmt_sig(v, 3) : std::string("n/a"); }

// Measured, reconstructed and (when given) reference force over a few tooth periods in the
// middle of the harmonic window (or of the evaluation window).
render::Figure time_figure(const ForceRecordResult& r, const ForceAxisResult& ax) {
  const double fs = r.sample_rate_hz;
  const forcerec::IndexWindow& w =
      r.harmonic_window.size() > 0 ? r.harmonic_window : r.evaluation_window;
  const Eigen::Index len = std::min<Eigen::Index>(
      w.size(), r.tooth_freq_hz > 0
                    ? static_cast<Eigen::Index>(std::ceil(kTimePeriods * fs / r.tooth_freq_hz)) + 1
                    : static_cast<Eigen::Index>(0.02 * fs));
  const Eigen::Index k0 = w.begin + (w.size() - len) / 2;
  std::vector<double> t(static_cast<std::size_t>(len));
  for (Eigen::Index k = 0; k < len; ++k) t[static_cast<std::size_t>(k)] = 1e3 * (k0 + k) / fs;
  render::Figure fig;
  fig.height_in = 3.4;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "time [ms]";
  a.y_label = std::string("F") + ax.axis + " [N]";
  a.legend = render::LegendPosition::kAuto;
  a.series.emplace_back(t, to_vector(ax.measured_N.segment(k0, len)), "measured",
                        render::SeriesStyle::kLine, "#999999");
  if (ax.reference_N.size() == ax.measured_N.size()) {
    a.series.emplace_back(t, to_vector(ax.reference_N.segment(k0, len)), "reference",
                          render::SeriesStyle::kDashedLine, "#000000");
  }
  for (int i = 0; i < 3; ++i) {
    const auto& m = ax.methods[static_cast<std::size_t>(i)];
    if (!m.ok) continue;
    a.series.emplace_back(t, to_vector(m.force_N.segment(k0, len)), kNames[i],
                          render::SeriesStyle::kLine, kMethodColours[i]);
  }
  return fig;
}

// Harmonic amplitudes at multiples of f_tp (top) over the model's |G| (bottom).
render::Figure spectrum_figure(const ForceRecordResult& r, const ForceAxisResult& ax) {
  render::Figure fig;
  fig.height_in = 4.4;
  fig.share_x = true;
  render::Axes& top = fig.panels.emplace_back();
  top.y_label = std::string("|A_h|, F") + ax.axis + " [N]";
  top.log_y = true;
  top.legend = render::LegendPosition::kAuto;
  top.relative_height = 1.6;
  const auto f_of = [&](std::size_t n) {
    std::vector<double> f(n);
    for (std::size_t h = 0; h < n; ++h) f[h] = (h + 1.0) * r.tooth_freq_hz;
    return f;
  };
  if (ax.reference_harmonics) {
    const auto& rh = ax.reference_harmonics->amplitudes_N;
    top.series.emplace_back(f_of(rh.size()), rh, "reference", render::SeriesStyle::kPoints,
                            "#000000");
  }
  const auto& mh = ax.measured_harmonics.amplitudes_N;
  top.series.emplace_back(f_of(mh.size()), mh, "measured", render::SeriesStyle::kLinePoints,
                          "#999999");
  for (int i = 0; i < 3; ++i) {
    const auto& m = ax.methods[static_cast<std::size_t>(i)];
    if (!m.ok) continue;
    const auto& h = m.harmonics.amplitudes_N;
    top.series.emplace_back(f_of(h.size()), h, kNames[i], render::SeriesStyle::kLinePoints,
                            kMethodColours[i]);
  }
  const double f_hi = std::max(0.5 * r.sample_rate_hz, 1.0);
  top.x_range = render::Range{0.0, f_hi};
  // `top` is not used below: adding a panel may move the vector's elements.
  render::Axes& bottom = fig.panels.emplace_back();
  bottom.x_label = "frequency [Hz]";
  bottom.y_label = "|G| [N/N]";
  bottom.log_y = true;
  std::vector<double> f, g;
  for (int i = 1; i <= 400; ++i) {
    const double fr = f_hi * i / 400.0;
    f.push_back(fr);
    g.push_back(std::abs(forcerec::transfer_response(ax.model->model, fr)));
  }
  bottom.series.emplace_back(f, g, "model " + ax.frf_test, render::SeriesStyle::kLine, "#000000");
  bottom.x_range = render::Range{0.0, f_hi};
  return fig;
}

// One log-log panel for a tuning curve per axis (E(S), the L-curve).
constexpr const char* kAxisColours[3] = {"#0072B2", "#D55E00", "#009E73"};
render::Figure tuning_figure(const std::string& x_label, const std::string& y_label) {
  render::Figure fig;
  fig.height_in = 3.2;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = x_label;
  a.y_label = y_label;
  a.log_x = true;
  a.log_y = true;
  a.legend = render::LegendPosition::kAuto;
  return fig;
}

// E(S) of every axis tuned by the knee, with the chosen S.
render::Figure akf_error_figure(const ForceRecordResult& r) {
  render::Figure fig = tuning_figure("S [N^2]", "E(S) [N]");
  render::Axes& a = fig.panels.front();
  int i = 0;
  for (const auto& ax : r.axes) {
    const auto& m = ax.methods[0];
    if (!ax.done || !m.ok || !m.akf.S_from_knee) continue;
    const char* c = kAxisColours[i++ % 3];
    a.series.emplace_back(to_vector(m.akf.S_grid_N2), to_vector(m.akf.E),
                          std::string("axis ") + ax.axis, render::SeriesStyle::kLine, c);
    if (m.akf.knee_index >= 0) {
      a.series.emplace_back(std::vector<double>{m.akf.S_N2},
                            std::vector<double>{m.akf.E(m.akf.knee_index)},
                            std::string("knee, ") + ax.axis, render::SeriesStyle::kPoints, c);
    }
  }
  return fig;
}

// The L-curves of rd (circulant screen) with the alpha used.
render::Figure lcurve_figure(const ForceRecordResult& r) {
  render::Figure fig = tuning_figure("||G f - y|| [N]", "||f|| [N]");
  render::Axes& a = fig.panels.front();
  int i = 0;
  for (const auto& ax : r.axes) {
    const auto& m = ax.methods[2];
    if (!ax.done || !m.ok || m.rd.lcurve.empty()) continue;
    const char* c = kAxisColours[i++ % 3];
    std::vector<double> x, y;
    for (const auto& p : m.rd.lcurve) {
      x.push_back(p.residual_norm_N);
      y.push_back(p.solution_norm_N);
    }
    a.series.emplace_back(x, y, std::string("axis ") + ax.axis, render::SeriesStyle::kLine, c);
    a.series.emplace_back(std::vector<double>{m.rd.residual_norm_N},
                          std::vector<double>{m.rd.solution_norm_N},
                          std::string("alpha used, ") + ax.axis, render::SeriesStyle::kPoints, c);
  }
  return fig;
}

bool any_knee(const ForceRecordResult& r) {
  for (const auto& ax : r.axes) {
    if (ax.done && ax.methods[0].ok && ax.methods[0].akf.S_from_knee) return true;
  }
  return false;
}

bool any_lcurve(const ForceRecordResult& r) {
  for (const auto& ax : r.axes) {
    if (ax.done && ax.methods[2].ok && !ax.methods[2].rd.lcurve.empty()) return true;
  }
  return false;
}

std::string tuning_text(const ForceMethodResult& m) {
  if (m.id == "akf")
    return "S = " + fmt_sig(m.tuning, 3) + " N^2" + (m.akf.S_from_knee ? " (knee)" : "");
  if (m.id == "smo") return "rho = " + fmt_sig(m.tuning, 3) + " N/s";
  return "alpha = " + fmt_sig(m.tuning, 3) + " (" + forcerec::to_string(m.rd.rule) + ")";
}

std::string harmonics_text(const std::vector<double>& h) {
  std::string s;
  for (std::size_t i = 0; i < h.size() && i < 3; ++i) s += (i ? ", " : "") + fmt_sig(h[i], 3);
  return s.empty() ? std::string("n/a") : s;
}

}  // namespace

void ForceRecordKind::figures(const CampaignResults&, const TestOutcome& out,
                              FigureJobs& jobs) const {
  const auto& r = out.result_of<ForceRecordResult>();
  const std::string stem = figure_stem("force-record", out.spec->id);
  for (const auto& ax : r.axes) {
    if (!ax.done) continue;
    const std::string a(1, ax.axis);
    jobs.add(out.spec->id, "time-" + a, stem + "time-" + a, time_figure(r, ax));
    jobs.add(out.spec->id, "spectrum-" + a, stem + "spectrum-" + a, spectrum_figure(r, ax));
  }
  if (any_knee(r)) jobs.add(out.spec->id, "akf-error", stem + "akf-error", akf_error_figure(r));
  if (any_lcurve(r)) jobs.add(out.spec->id, "rd-lcurve", stem + "rd-lcurve", lcurve_figure(r));
}

json ForceRecordKind::report_section(const CampaignResults&,
                                     const std::vector<const TestOutcome*>& ok,
                                     const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  json comparison = json::array();  // every record and axis: the three methods side by side
  bool any_reference = false, any_other = false;
  json drift = json::array();
  for (const TestOutcome* t : ok) {
    const auto& r = t->result_of<ForceRecordResult>();
    const auto& s = t->spec->kind_spec<ForceRecordSpec>();
    const std::string& id = t->spec->id;
    json j;
    j["id"] = id;
    j["rpm"] = fmt_sig(s.spindle_rpm, 5);
    j["operation"] = s.operation.empty() ? std::string("cut") : s.operation;
    j["tooth_hz"] = fmt_sig(r.tooth_freq_hz, 5);
    j["fs_hz"] = fmt_sig(r.sample_rate_hz, 5);
    j["seconds"] = fmt_sig(static_cast<double>(r.samples) / r.sample_rate_hz, 4);
    j["harmonics"] = r.harmonic_count;
    j["force_file"] = force_file_path(id);
    json axes = json::array();
    for (const auto& ax : r.axes) {
      const std::string a(1, ax.axis);
      json e;
      e["axis"] = a;
      e["done"] = ax.done;
      e["skip_reason"] = ax.skip_reason;
      if (!ax.done) {
        axes.push_back(e);
        continue;
      }
      const bool ref = ax.measured_nrmse_pct.has_value();
      any_reference = any_reference || ref;
      e["frf_test"] = ax.frf_test;
      e["R_N2"] = fmt_sig(ax.noise_var_N2, 3);
      e["R_source"] = ax.noise_from_air ? "air window" : "noise_var_N2";
      e["has_reference"] = ref;
      json rows = json::array();
      rows.push_back({{"method", "measured"},
                      {"tuning", ""},
                      {"mean_N", fmt_sig(ax.measured_harmonics.mean_N, 4)},
                      {"h", harmonics_text(ax.measured_harmonics.amplitudes_N)},
                      {"nrmse", ref ? pct(*ax.measured_nrmse_pct) : "n/a"},
                      {"fit", ""},
                      {"lag", ""},
                      {"runtime", ""}});
      if (ax.reference_harmonics) {
        rows.push_back({{"method", "reference"},
                        {"tuning", ""},
                        {"mean_N", fmt_sig(ax.reference_harmonics->mean_N, 4)},
                        {"h", harmonics_text(ax.reference_harmonics->amplitudes_N)},
                        {"nrmse", ""},
                        {"fit", ""},
                        {"lag", ""},
                        {"runtime", ""}});
      }
      json cmp = {{"id", id}, {"axis", a}, {"measured", ref ? pct(*ax.measured_nrmse_pct) : "n/a"}};
      for (const auto& m : ax.methods) {
        if (!m.ok) {
          rows.push_back({{"method", m.id},
                          {"tuning", "failed: " + m.message},
                          {"mean_N", ""},
                          {"h", ""},
                          {"nrmse", ""},
                          {"fit", ""},
                          {"lag", ""},
                          {"runtime", ""}});
          cmp[m.id] = "failed";
          continue;
        }
        rows.push_back({{"method", m.id},
                        {"tuning", tuning_text(m)},
                        {"mean_N", fmt_sig(m.harmonics.mean_N, 4)},
                        {"h", harmonics_text(m.harmonics.amplitudes_N)},
                        {"nrmse", m.error ? pct(m.error->nrmse_pct) : "n/a"},
                        {"fit", m.error ? pct(m.error->fit_pct) : "n/a"},
                        {"lag", m.error ? std::to_string(m.error->lag_samples) : "n/a"},
                        {"runtime", fmt_sig(m.runtime_s, 2)}});
        // Without a reference the comparison shows the first harmonic (N).
        cmp[m.id] = m.error ? pct(m.error->nrmse_pct)
                            : (m.harmonics.amplitudes_N.empty()
                                   ? std::string("n/a")
                                   : fmt_sig(m.harmonics.amplitudes_N[0], 3) + " N");
      }
      comparison.push_back(cmp);
      for (const auto& o : ax.other_models) {
        any_other = true;
        json d = {{"id", id}, {"axis", a}, {"model", o.frf_test}, {"used", ax.frf_test}};
        for (std::size_t i = 0; i < 3; ++i) {
          const auto& m = o.methods[i];
          const auto& base = ax.methods[i];
          d[m.id] = !m.ok ? std::string("failed")
                    : m.error && base.error
                        ? pct(m.error->nrmse_pct) + " (" + pct(base.error->nrmse_pct) + ")"
                        : "h1 " + harmonics_text({m.harmonics.amplitudes_N.empty()
                                                      ? NAN
                                                      : m.harmonics.amplitudes_N[0]});
        }
        drift.push_back(d);
      }
      e["rows"] = rows;
      e["time_figure"] = figures.of(id, "time-" + a);
      e["spectrum_figure"] = figures.of(id, "spectrum-" + a);
      axes.push_back(e);
    }
    j["axes"] = axes;
    j["akf_figure"] = figures.of(id, "akf-error");
    j["has_akf_figure"] = !figures.of(id, "akf-error").empty();
    j["lcurve_figure"] = figures.of(id, "rd-lcurve");
    j["has_lcurve_figure"] = !figures.of(id, "rd-lcurve").empty();
    j["has_warnings"] = !t->warnings.empty();
    j["warnings"] = t->warnings;
    tests.push_back(j);
  }
  return {{"toc", json::array({{{"anchor", "force-record"},
                                {"title", "Force reconstruction behind the dynamometer"}}})},
          {"force_records", tests},
          {"force_comparison", comparison},
          {"force_comparison_metric",
           any_reference ? "NRMSE against the reference (%)" : "first harmonic amplitude"},
          {"force_drift", drift},
          {"has_force_drift", any_other}};
}

void ForceRecordKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                                    TruthComparison& c) const {
  const auto& r = out.result_of<ForceRecordResult>();
  const YAML::Node& v = *in.entry;
  const std::string& id = out.spec->id;
  const YAML::Node axes = v["axes"];
  if (!axes || !axes.IsMap()) return;
  for (const auto& ax : r.axes) {
    const std::string a(1, ax.axis);
    const YAML::Node e = axes[a];
    if (!ax.done || !e || !e.IsMap()) continue;
    if (!ax.noise_from_air) {
      // noise_var_N2 given: nothing estimated, no row.
    } else {
      add_truth_row(c, a + ".noise_var_N2", id, truth_number(e, "noise_var_N2"), ax.noise_var_N2);
    }
    const YAML::Node th = e["harmonics_N"];
    for (const auto& m : ax.methods) {
      if (!m.ok) continue;
      add_truth_row(c, a + "." + m.id + ".mean_N", id, truth_number(e, "mean_N"),
                    m.harmonics.mean_N);
      if (!th || !th.IsSequence()) continue;
      for (std::size_t h = 0; h < 3 && h < th.size() && h < m.harmonics.amplitudes_N.size(); ++h) {
        double tv = NAN;
        try {
          tv = th[h].as<double>();
        } catch (const YAML::Exception&) {
        }
        add_truth_row(c, a + "." + m.id + ".harmonic" + std::to_string(h + 1) + "_N", id, tv,
                      m.harmonics.amplitudes_N[h]);
      }
    }
  }
}

}  // namespace chatterlab::app
