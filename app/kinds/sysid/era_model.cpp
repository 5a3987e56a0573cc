// The ERA model step shared by kinds frf and sweep-frf (sysid_kinds.h, docs/sysid.md).
#include <cmath>
#include <complex>

#include "analysis/common/constants.h"
#include "app/core/format.h"
#include "app/core/input_boundary.h"
#include "app/core/signals.h"
#include "app/kinds/sysid/sysid_kinds.h"
#include "app/pipeline/pipeline.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;

EraModelResult run_era_model(const TestSpec& t, const Eigen::VectorXd& f_hz,
                             const Eigen::VectorXcd& G, const std::string& input_unit,
                             const std::string& output_unit, const sysid::EraOptions& options) {
  EraModelResult m;
  m.input_unit = input_unit;
  m.output_unit = output_unit;
  m.era = sysid::era_identify(f_hz, G, t.sample_rate_hz, options);
  if (m.era.summary.ok()) {
    auto d = std::make_shared<DriveModel>();
    d->id = t.id;
    d->model = m.era.model;
    d->input_unit = input_unit;
    d->output_unit = output_unit;
    m.drive = std::move(d);
  }
  return m;
}

std::string value::describe_drive_model(const std::string& name) {
  return name.rfind("drive-model:", 0) == 0 ? "the ERA model of " + name.substr(12) : "";
}

std::string underscored(std::string id) {
  for (char& c : id) {
    if (c == '/') c = '_';
  }
  return id;
}

namespace {

json matrix_rows(const Eigen::MatrixXd& A) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index j = 0; j < A.cols(); ++j) row.push_back(A(i, j));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

json era_model_json(const EraModelResult& m) {
  const auto& e = m.era;
  json poles = json::array();
  for (Eigen::Index i = 0; i < e.poles.size(); ++i) {
    poles.push_back({e.poles[i].real(), e.poles[i].imag()});
  }
  json modes = json::array();
  for (const auto& md : e.modes) modes.push_back({{"fn_hz", md.fn_hz}, {"zeta", md.zeta}});
  json model = {
      {"method", "era-gavish-donoho-schur"},
      {"sample_time_s", 1.0 / e.model.sample_rate_hz},
      {"order", e.model.order()},
      {"order_era", e.realization.model.order()},
      {"order_threshold", e.realization.order_by_threshold},
      {"unstable_removed", e.unstable_removed},
      {"hankel_rows", e.realization.hankel_size},
      {"hankel_cols", e.realization.hankel_size},
      {"markov_samples", e.markov_length},
      {"singular_value_threshold", e.realization.threshold},
      {"singular_values", number_array(e.realization.singular_values.head(
                              std::min<Eigen::Index>(e.realization.singular_values.size(), 200)))},
      {"decoupling_residual", number_or_null(e.decoupling_residual)},
      {"A", matrix_rows(e.model.A)},
      {"B", number_array(e.model.B)},
      {"C", number_array(e.model.C.transpose())},
      {"D", e.model.D},
      {"poles_z", poles},
      {"modes", modes},
      {"dc_gain", number_or_null(e.dc_gain)},
      {"fit_pct", number_or_null(e.fit_pct)},
      {"fit_points", e.fit_f_hz.size()},
      {"svd_s", e.realization.svd_s},
      {"runtime_s", e.runtime_s}};
  return {{"input_unit", m.input_unit}, {"output_unit", m.output_unit}, {"model", model}};
}

std::string era_model_note(const EraModelResult& m) {
  const auto& e = m.era;
  std::string s = "order " + std::to_string(e.model.order());
  if (e.unstable_removed > 0) {
    s += " (ERA " + std::to_string(e.realization.model.order()) + ", " +
         std::to_string(e.unstable_removed) + " unstable removed)";
  }
  return s + ", fit " + fmt_sig(e.fit_pct, 4) + " %";
}

json era_model_section(const TestOutcome& t, const EraModelResult& m, const FigureSet& figures) {
  const auto& e = m.era;
  json j;
  j["id"] = t.spec->id;
  j["order"] = e.model.order();
  j["order_era"] = e.realization.model.order();
  j["order_threshold"] = e.realization.order_by_threshold;
  j["unstable_removed"] = e.unstable_removed;
  j["hankel"] = e.realization.hankel_size;
  j["threshold"] = fmt_sig(e.realization.threshold, 3);
  j["fit_pct"] = fmt_sig(e.fit_pct, 4);
  j["dc_gain"] = fmt_sig(e.dc_gain, 4);
  j["units"] = m.output_unit + " per " + m.input_unit;
  j["sample_rate_hz"] = fmt_sig(e.model.sample_rate_hz, 6);
  j["svd_ms"] = fmt_sig(e.realization.svd_s * 1e3, 3);
  j["runtime_ms"] = fmt_sig(e.runtime_s * 1e3, 3);
  json modes = json::array();
  int i = 1;
  for (const auto& md : e.modes) {
    modes.push_back({{"n", i++},
                     {"fn_hz", fmt_sig(md.fn_hz, 4)},
                     {"zeta_pct", fmt_sig(md.zeta * 100.0, 3)},
                     {"radius", fmt_sig(std::abs(md.z), 5)}});
  }
  j["modes"] = modes;
  j["has_modes"] = !modes.empty();
  j["figure_frf"] = figures.of(t.spec->id, "frf");
  j["figure_sv"] = figures.of(t.spec->id, "singular-values");
  j["has_warnings"] = !t.warnings.empty();
  j["warnings"] = t.warnings;
  return j;
}

void era_model_truth(const TruthInput& in, const TestOutcome& out, const EraModelResult& m,
                     TruthComparison& c) {
  const YAML::Node& v = *in.entry;
  const std::string& id = out.spec->id;
  const auto& e = m.era;
  const YAML::Node modes = v["modes"];
  if (modes && modes.IsSequence()) {
    for (std::size_t i = 0; i < modes.size(); ++i) {
      const double fn = truth_number(modes[i], "fn_hz");
      if (!std::isfinite(fn) || e.modes.empty()) continue;
      // A mode whose peak is below three times the FRF's noise is not expected back.
      if (truth_number(modes[i], "peak_to_noise") < 3.0) continue;
      const sysid::DiscreteMode* best = &e.modes.front();
      for (const auto& md : e.modes) {
        if (std::abs(md.fn_hz - fn) < std::abs(best->fn_hz - fn)) best = &md;
      }
      const std::string q = "mode" + std::to_string(i + 1) + ".";
      add_truth_row(c, q + "fn_hz", id, fn, best->fn_hz);
      add_truth_row(c, q + "zeta", id, truth_number(modes[i], "zeta"), best->zeta);
    }
  }
  add_truth_row(c, "dc_gain", id, truth_number(v, "dc_gain_A_per_Nm"), e.dc_gain);
  add_truth_row(c, "order", id, truth_number(v, "order"), static_cast<double>(e.model.order()));
  // The model's fit to the noise-free FRF of truth.yaml's frf_file (a CSV freq_hz, re, im
  // inside the campaign), over check_band_hz when given, else 0 < f <= rate/2: 100 is exact.
  const YAML::Node file = v["frf_file"];
  if (file && file.IsScalar() && in.results) {
    const InputFileCheck chk =
        check_input_file(in.results->campaign.root, in.results->campaign.root, file.Scalar());
    if (!chk.ok()) return;
    try {
      DataSpec d;
      d.file = chk.path;
      d.relative_file = file.Scalar();
      const SignalTable t = SignalTable::open(d, file.Scalar());
      const Eigen::VectorXd f = t.channel("freq_hz"), re = t.channel("re"), im = t.channel("im");
      double lo = 0.0, hi = 0.5 * e.model.sample_rate_hz;
      if (const YAML::Node b = v["check_band_hz"]; b && b.IsSequence() && b.size() == 2) {
        lo = b[0].as<double>(lo);
        hi = b[1].as<double>(hi);
      }
      std::vector<Eigen::Index> keep;
      for (Eigen::Index k = 0; k < f.size(); ++k) {
        if (f[k] > 0.0 && f[k] >= lo && f[k] <= hi) keep.push_back(k);
      }
      if (keep.size() < 2) return;
      Eigen::VectorXd fk(static_cast<Eigen::Index>(keep.size()));
      Eigen::VectorXcd Gk(fk.size());
      for (std::size_t k = 0; k < keep.size(); ++k) {
        fk[static_cast<Eigen::Index>(k)] = f[keep[k]];
        Gk[static_cast<Eigen::Index>(k)] = {re[keep[k]], im[keep[k]]};
      }
      add_truth_row(c, "frf_fit_vs_truth_pct", id, 100.0,
                    sysid::frf_fit_pct(Gk, sysid::frequency_response(e.model, fk)));
    } catch (const InputError&) {
      // An unreadable truth file gives no row.
    }
  }
}

render::Figure era_frf_figure(const EraModelResult& m) {
  const auto& e = m.era;
  std::vector<double> x, mag, fit, ph, phfit;
  for (Eigen::Index i = 0; i < e.fit_f_hz.size(); ++i) {
    x.push_back(e.fit_f_hz[i]);
    mag.push_back(std::abs(e.fit_G[i]));
    fit.push_back(std::abs(e.fit_G_model[i]));
    ph.push_back(std::arg(e.fit_G[i]) * kRadToDeg);
    phfit.push_back(std::arg(e.fit_G_model[i]) * kRadToDeg);
  }
  render::Figure fig;
  fig.height_in = 4.2;
  fig.share_x = true;
  render::Axes& a = fig.panels.emplace_back();
  const auto grouped = [](const std::string& u) {
    return u.find_first_of("*/ ") == std::string::npos ? u : "(" + u + ")";
  };
  a.y_label = "|G| [" + grouped(m.output_unit) + "/" + grouped(m.input_unit) + "]";
  a.log_y = true;
  a.relative_height = 2;
  a.series = {{x, mag, "measured FRF", render::SeriesStyle::kLine, "#0072B2"},
              {x, fit, "ERA model, order " + std::to_string(e.model.order()),
               render::SeriesStyle::kDashedLine, "#D55E00"}};
  render::Axes& p = fig.panels.emplace_back();
  p.x_label = "frequency [Hz]";
  p.y_label = "phase [deg]";
  p.series = {{x, ph, "", render::SeriesStyle::kLine, "#0072B2"},
              {x, phfit, "", render::SeriesStyle::kDashedLine, "#D55E00"}};
  return fig;
}

render::Figure era_singular_value_figure(const EraModelResult& m) {
  const auto& r = m.era.realization;
  const Eigen::Index n = std::min<Eigen::Index>(r.singular_values.size(), 120);
  std::vector<double> idx, sv, kept_x, kept_y;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(r.singular_values[i] > 0.0)) break;
    idx.push_back(static_cast<double>(i + 1));
    sv.push_back(r.singular_values[i]);
    if (i < m.era.realization.model.order()) {
      kept_x.push_back(static_cast<double>(i + 1));
      kept_y.push_back(r.singular_values[i]);
    }
  }
  render::Figure fig;
  fig.height_in = 3.0;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "index i";
  a.y_label = "singular value of H";
  a.log_y = true;
  a.legend = render::LegendPosition::kAuto;
  const double last = idx.empty() ? 1.0 : idx.back();
  a.series = {{idx, sv, "singular values", render::SeriesStyle::kPoints, "#0072B2"},
              {kept_x, kept_y, "kept (order " + std::to_string(r.model.order()) + ")",
               render::SeriesStyle::kPoints, "#D55E00"},
              {{1.0, last},
               {r.threshold, r.threshold},
               "Gavish-Donoho threshold",
               render::SeriesStyle::kDashedLine,
               "#555555"}};
  return fig;
}

}  // namespace chatterlab::app
