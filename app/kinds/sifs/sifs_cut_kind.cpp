// Kind `sifs-cut` (format section 6, 003 ch. 4-6): see sifs_kinds.h and docs/sifs.md.
#include <cmath>
#include <fstream>
#include <limits>

#include "analysis/common/constants.h"
#include "analysis/signal/resample.h"
#include "app/core/archive_analysis.h"
#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/core/parallel.h"
#include "app/core/vectors.h"
#include "app/kinds/common/conditions.h"
#include "app/kinds/sifs/sifs_common.h"
#include "app/kinds/sifs/sifs_kinds.h"
#include "app/kinds/sifs/sifs_synth.h"
#include "app/pipeline/cached_result.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::Index to_index(double t_s, double fs, Eigen::Index n) {
  return std::clamp<Eigen::Index>(static_cast<Eigen::Index>(std::llround(t_s * fs)), 0, n);
}

double rms(const Eigen::Ref<const Eigen::VectorXd>& x) {
  return x.size() ? std::sqrt(x.squaredNorm() / static_cast<double>(x.size())) : kNaN;
}

Eigen::VectorXd resampled(const signal::RationalResampler* rs, const Eigen::VectorXd& x) {
  return rs ? rs->apply(x) : x;
}

// Phase of c / c_ref in (-180, 180] degrees.
double phase_err_deg(std::complex<double> c, std::complex<double> ref) {
  double d = std::arg(c / ref) * kRadToDeg;
  if (d <= -180.0) d += 360.0;
  return d;
}

}  // namespace

std::vector<std::string> SifsCutKind::keys() const {
  return {"spindle_rpm",
          "air_window_s",
          "cut_window_s",
          "taps",
          "dynamometer",
          "band_hz",
          "filter_rate_hz",
          "unbalance_harmonics",
          "gain",
          "tool_length_mm",
          "operation",
          "axial_depth_mm",
          "radial_immersion_mm",
          "feed_per_tooth_mm"};
}

std::shared_ptr<const KindSpec> SifsCutKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto s = std::make_shared<SifsCutSpec>();
  s->spindle_rpm = r.required_double(root, "spindle_rpm");
  if (root["spindle_rpm"] && !(s->spindle_rpm > 0)) r.error("spindle_rpm", "must be > 0");
  if (auto a = read_interval(root, r, "air_window_s", true)) {
    s->air_lo_s = a->first;
    s->air_hi_s = a->second;
  }
  if (auto c = read_interval(root, r, "cut_window_s", true)) {
    s->cut_lo_s = c->first;
    s->cut_hi_s = c->second;
  }
  const YAML::Node taps = root["taps"];
  if (!taps || !taps.IsMap()) {
    r.error("taps", "is required: {x: <sifs-tap test id>, y: <sifs-tap test id>}");
  } else {
    r.check_keys(taps, {"x", "y"}, "taps");
    s->tap_x = r.required_string(taps, "x", "taps");
    s->tap_y = r.required_string(taps, "y", "taps");
  }
  if (const YAML::Node d = root["dynamometer"]) {
    if (!d.IsMap()) {
      r.error("dynamometer", "must be {channels: [dx, dy, dz], angle_deg: a}");
    } else {
      r.check_keys(d, {"channels", "angle_deg"}, "dynamometer");
      const auto ch = r.string_list(d, "channels", true, "dynamometer");
      if (ch.size() != 3) {
        r.error("dynamometer.channels", "must name three channels (x, y, z of the dynamometer)");
      } else {
        s->dyn_channels = {ch[0], ch[1], ch[2]};
        s->has_dynamometer = true;
      }
      s->dyn_angle_deg = r.required_double(d, "angle_deg", "dynamometer");
    }
  }
  s->band_hz = read_interval(root, r, "band_hz", false);
  if (auto f = r.optional_double(root, "filter_rate_hz")) {
    if (!(*f > 0)) {
      r.error("filter_rate_hz", "must be > 0");
    } else {
      s->filter_rate_hz = *f;
    }
  }
  if (auto h = r.optional_double(root, "unbalance_harmonics")) {
    if (*h < 0 || *h > 20 || std::floor(*h) != *h) {
      r.error("unbalance_harmonics", "must be a whole number from 0 to 20");
    } else {
      s->unbalance_harmonics = static_cast<int>(*h);
    }
  }
  if (auto g = r.optional_string(root, "gain")) {
    if (*g == "steady-state") {
      s->gain = sifs::GainMode::kSteadyState;
    } else if (*g != "time-varying") {
      r.error("gain", "must be time-varying or steady-state, not '" + *g + "'");
    }
  }
  s->tool_length_mm = read_tool_length(root, r);
  for (const char* k : {"axial_depth_mm", "radial_immersion_mm", "feed_per_tooth_mm"}) {
    r.optional_double(root, k);
  }
  r.optional_string(root, "operation");
  if (s->cut_hi_s > 0 && s->air_hi_s > s->cut_lo_s && s->air_lo_s < s->cut_hi_s) {
    r.error("air_window_s",
            "overlaps cut_window_s: the air window is spindle at speed, tool "
            "not engaged");
  }
  return s;
}

std::vector<std::string> SifsCutKind::check_campaign(const CampaignSpec& c,
                                                     const TestSpec& t) const {
  std::vector<std::string> e;
  if (auto m = needs_tool(c, t)) e.push_back(*m);
  const auto& s = t.kind_spec<SifsCutSpec>();
  const std::pair<const char*, const std::string*> taps[2] = {{"x", &s.tap_x}, {"y", &s.tap_y}};
  for (const auto& [axis, id] : taps) {
    if (id->empty()) continue;
    const TestSpec* tap = nullptr;
    for (const auto& other : c.tests) {
      if (other.id == *id) tap = &other;
    }
    if (!tap) {
      e.push_back(t.yaml_label + ": key 'taps." + axis + "' names '" + *id +
                  "', which is not a test of the campaign");
    } else if (tap->kind != "sifs-tap") {
      e.push_back(t.yaml_label + ": key 'taps." + axis + "' names '" + *id + "', a " + tap->kind +
                  " test, not a sifs-tap test");
    } else if (tap->params) {
      const auto* ts = dynamic_cast<const SifsTapSpec*>(tap->params.get());
      if (ts && sifs::to_string(ts->axis) != std::string(axis)) {
        e.push_back(t.yaml_label + ": key 'taps." + axis + "' names '" + *id + "', whose axis is " +
                    sifs::to_string(ts->axis));
      }
    }
  }
  return e;
}

std::vector<std::string> SifsCutKind::required_channels(const TestSpec& t) const {
  std::vector<std::string> c = kWasherChannels;
  const auto& s = t.kind_spec<SifsCutSpec>();
  if (s.has_dynamometer) c.insert(c.end(), s.dyn_channels.begin(), s.dyn_channels.end());
  return c;
}

std::vector<std::string> SifsCutKind::check_record(const TestSpec& t, double duration_s) const {
  const auto& s = t.kind_spec<SifsCutSpec>();
  std::vector<std::string> e;
  if (auto m = window_outside(t, "air_window_s", s.air_hi_s, duration_s)) e.push_back(*m);
  if (auto m = window_outside(t, "cut_window_s", s.cut_hi_s, duration_s)) e.push_back(*m);
  const double fr = s.filter_rate_hz.value_or(t.sample_rate_hz);
  if (s.band_hz && s.band_hz->first >= 0.45 * fr) {
    e.push_back(t.yaml_label + ": key 'band_hz' starts at " + fmt_sig(s.band_hz->first, 6) +
                " Hz, above 0.45 x the filter rate (" + fmt_sig(0.45 * fr, 6) + " Hz)");
  }
  return e;
}

std::vector<Need> SifsCutKind::needs(const TestSpec& t) const {
  const auto& s = t.kind_spec<SifsCutSpec>();
  return {{value::kSifsCalibration, true},
          {value::sifs_tap(s.tap_x), true},
          {value::sifs_tap(s.tap_y), true}};
}

std::vector<std::string> SifsCutKind::provides(const TestSpec&) const {
  return {value::kSifsCutSummary};
}

std::string SifsCutKind::describe_value(const std::string& name) const {
  return name == value::kSifsCutSummary ? "a compensated cut" : "";
}

void SifsCutKind::run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
                      TestOutcome& out) const {
  const auto& s = t.kind_spec<SifsCutSpec>();
  const SifsCalibration* cal = in.first<SifsCalibration>(value::kSifsCalibration);
  const std::string tap_ids[2] = {s.tap_x, s.tap_y};
  const SifsTapData* taps[2] = {nullptr, nullptr};
  for (int a = 0; a < 2; ++a) {
    const auto* p = in.first<std::shared_ptr<const SifsTapData>>(value::sifs_tap(tap_ids[a]));
    if (p) taps[a] = p->get();
  }
  if (!cal || !taps[0] || !taps[1]) {
    const std::string why =
        !cal       ? in.why_missing(value::kSifsCalibration, "the sensor's calibration matrix")
        : !taps[0] ? in.why_missing(value::sifs_tap(s.tap_x), "the sensor model of " + s.tap_x)
                   : in.why_missing(value::sifs_tap(s.tap_y), "the sensor model of " + s.tap_y);
    out.status.fail(why);
    out.failure = Failure::kInput;
    return;
  }
  const SignalTable table = SignalTable::open(t.data, t.data_label());
  const sifs::Pairs pairs = sifs::pair_signals(read_washers(table, t));
  const Eigen::Matrix3d C = calibration_for(*cal, t, s.tool_length_mm, out.warnings);
  const Eigen::Matrix<double, Eigen::Dynamic, 3> fm = pairs * C.transpose();
  const double fs = t.sample_rate_hz;
  const double fr = s.filter_rate_hz.value_or(fs);
  const Eigen::Index n = fm.rows();

  auto res = std::make_unique<SifsCutResult>();
  res->spindle_rpm = s.spindle_rpm;
  res->teeth = ctx.campaign->tool ? ctx.campaign->tool->teeth : 0;
  res->spindle_hz = s.spindle_rpm / 60.0;
  res->tooth_passing_hz = res->teeth * res->spindle_hz;  // 003 eq. 2-1
  res->fs_hz = fs;
  res->filter_rate_hz = fr;
  res->has_reference = s.has_dynamometer;
  if (!(res->tooth_passing_hz < 0.5 * fr)) {
    throw InputError(
        t.yaml_label + ": the tooth-passing frequency (" + fmt_sig(res->tooth_passing_hz, 6) +
        " Hz) must lie below the filter's Nyquist frequency (" + fmt_sig(0.5 * fr, 6) + " Hz)");
  }
  std::unique_ptr<signal::RationalResampler> rs;
  if (std::abs(fr - fs) > 1e-9 * fs) {
    try {
      rs = std::make_unique<signal::RationalResampler>(fs, fr);
    } catch (const InputError& e) {
      throw InputError(t.yaml_label + ": key 'filter_rate_hz': " + e.what());
    }
  }
  const double band_lo = s.band_hz ? s.band_hz->first : 0.0;
  const double band_hi = s.band_hz ? s.band_hz->second : 0.4 * fr;
  const std::vector<int> harmonics =
      sifs::analysed_harmonics(res->spindle_hz, band_lo, band_hi, fr);
  if (harmonics.empty()) {
    throw InputError(t.yaml_label + ": no spindle harmonic (" + fmt_sig(res->spindle_hz, 6) +
                     " Hz and its multiples) lies in band_hz [" + fmt_sig(band_lo, 6) + ", " +
                     fmt_sig(band_hi, 6) + "] Hz below 0.45 x the filter rate");
  }

  // Reference forces in machine axes (format step 6), air-window mean removed.
  Eigen::Matrix<double, Eigen::Dynamic, 2> ref;
  if (s.has_dynamometer) {
    const Eigen::VectorXd dx = table.channel(s.dyn_channels[0], t.channel(s.dyn_channels[0]));
    const Eigen::VectorXd dy = table.channel(s.dyn_channels[1], t.channel(s.dyn_channels[1]));
    const double a = s.dyn_angle_deg / kRadToDeg;
    ref.resize(n, 2);
    ref.col(0) = dx * std::cos(a) - dy * std::sin(a);
    ref.col(1) = dx * std::sin(a) + dy * std::cos(a);
    const Eigen::Index b = to_index(s.air_lo_s, fs, n), e = to_index(s.air_hi_s, fs, n);
    for (int k = 0; k < 2; ++k) ref.col(k).array() -= ref.col(k).segment(b, e - b).mean();
  }

  for (int a = 0; a < 2; ++a) {
    for (const auto& m : taps[a]->modes) {
      if (m.fn_hz < 0.5 * fr) continue;
      throw InputError(t.yaml_label + ": the sensor model of " + taps[a]->id + " has a mode at " +
                       fmt_sig(m.fn_hz, 5) + " Hz, at or above the filter's Nyquist frequency (" +
                       fmt_sig(0.5 * fr, 5) +
                       " Hz): raise filter_rate_hz, or fit that tap test in a band_hz below it");
    }
  }
  if (s.unbalance_harmonics * res->spindle_hz >= 0.5 * fs) {
    throw InputError(
        t.yaml_label + ": key 'unbalance_harmonics': " + std::to_string(s.unbalance_harmonics) +
        " x the spindle frequency (" + fmt_sig(res->spindle_hz, 6) +
        " Hz) reaches the record's Nyquist frequency (" + fmt_sig(0.5 * fs, 6) + " Hz)");
  }
  const Eigen::Index air_b = to_index(s.air_lo_s, fs, n), air_e = to_index(s.air_hi_s, fs, n);
  std::vector<int> ub_h;
  for (int h = 1; h <= s.unbalance_harmonics; ++h) ub_h.push_back(h);

  const Eigen::Index n_filter = rs ? rs->output_size(n) : n;
  res->cut_begin = to_index(s.cut_lo_s, fr, n_filter);
  res->cut_end = to_index(s.cut_hi_s, fr, n_filter);
  std::array<std::string, 2> errors;
  parallel_for(2, ctx.jobs, [&](std::size_t ai) {
    const int a = static_cast<int>(ai);
    SifsAxisResult& ax = res->axes[ai];
    try {
      // 1. Unbalance and offset over the air window (eq. 3-6 corrected), subtracted.
      Eigen::VectorXd f = fm.col(a);
      ax.unbalance = signal::fit_harmonics(f, fs, air_b, air_e, res->spindle_hz, ub_h);
      if (!ax.unbalance.summary.ok()) {
        errors[ai] = "unbalance fit: " + ax.unbalance.summary.message;
        return;
      }
      signal::subtract_harmonics(ax.unbalance, fs, f);
      // 2. To the filter rate; R_cut.
      ax.measured_n = resampled(rs.get(), f);
      const Eigen::Index m = ax.measured_n.size();
      const Eigen::Index ab = to_index(s.air_lo_s, fr, m), ae = to_index(s.air_hi_s, fr, m);
      ax.r_cut_n = rms(ax.measured_n.segment(ab, ae - ab));
      // 4. Tap sweep at this speed: q_opt.
      const SifsTapData& tap = *taps[ai];
      const sifs::TapSweepInput tin = tap_sweep_input(tap, fr, band_lo, band_hi, s.gain);
      ax.r_tap_n = tin.r_tap_n;
      ax.tap_curve = sifs::tap_sweep(tin, s.spindle_rpm, res->teeth);
      if (!ax.tap_curve.summary.ok()) {
        errors[ai] = "tap sweep on " + tap.id + ": " + ax.tap_curve.summary.message;
        return;
      }
      ax.q = ax.tap_curve.q_opt;
      ax.q_exponent = ax.tap_curve.best_exponent;
      // 3, 5. The augmented model and the filter.
      const sifs::CompensatorModel model =
          sifs::make_compensator(tap.modes, res->tooth_passing_hz, fr);
      ax.cond_F = model.cond_F;
      ax.obsv_rcond = model.obsv_rcond;
      Eigen::Index steps = 0;
      const StepSummary fs_sum = sifs::compensate(model, ax.q, ax.r_cut_n, s.gain, ax.measured_n,
                                                  &ax.compensated_n, &steps);
      if (!fs_sum.ok()) {
        errors[ai] = "filter: " + fs_sum.message;
        return;
      }
      const std::vector<std::string>* step_warnings[3] = {
          &ax.unbalance.summary.warnings, &ax.tap_curve.summary.warnings, &fs_sum.warnings};
      for (const auto* w : step_warnings)
        ax.warnings.insert(ax.warnings.end(), w->begin(), w->end());
      ax.gain_converged_s = kNaN;
      if (s.gain == sifs::GainMode::kTimeVarying) {
        if (steps >= 0) ax.gain_converged_s = static_cast<double>(steps) / fr;
        if (steps < 0 || steps > res->cut_begin) {
          ax.warnings.push_back(
              "the time-varying gain had not converged by the start of cut_window_s (" +
              (steps < 0 ? std::string("not within the record")
                         : "converged at " + fmt_sig(ax.gain_converged_s, 4) + " s") +
              "): the harmonics are those of a filter still settling");
        }
      }
      // 6. Harmonics over the cut window.
      ax.harmonics = harmonics;
      ax.c_measured = sifs::cut_harmonics(ax.measured_n, fr, res->cut_begin, res->cut_end,
                                          res->spindle_hz, harmonics);
      ax.c_compensated = sifs::cut_harmonics(ax.compensated_n, fr, res->cut_begin, res->cut_end,
                                             res->spindle_hz, harmonics);
      ax.rmse_compensated_n = ax.rmse_measured_n = kNaN;
      if (s.has_dynamometer) {
        ax.reference_n = resampled(rs.get(), ref.col(a));
        ax.c_reference = sifs::cut_harmonics(ax.reference_n, fr, res->cut_begin, res->cut_end,
                                             res->spindle_hz, harmonics);
        ax.rmse_compensated_n = sifs::spectral_rmse(ax.c_compensated, ax.c_reference);
        ax.rmse_measured_n = sifs::spectral_rmse(ax.c_measured, ax.c_reference);
        ax.cut_curve = sifs::cut_sweep(model, ax.r_cut_n, s.gain, ax.measured_n, res->cut_begin,
                                       res->cut_end, res->spindle_hz, harmonics, ax.c_reference);
        ax.warnings.insert(ax.warnings.end(), ax.cut_curve.summary.warnings.begin(),
                           ax.cut_curve.summary.warnings.end());
      }
      // 7. Usable bandwidth before and after.
      ax.bandwidth_before_hz = sifs::usable_bandwidth_hz(tap.modes, model, Eigen::VectorXd());
      const Eigen::VectorXd K = sifs::steady_gain(model, ax.q / ax.r_cut_n);
      ax.bandwidth_after_hz = K.size() ? sifs::usable_bandwidth_hz(tap.modes, model, K) : kNaN;
      ax.summary.succeed();
    } catch (const InputError& e) {
      errors[ai] = e.what();
    }
  });
  for (int a = 0; a < 2; ++a) {
    if (!errors[static_cast<std::size_t>(a)].empty()) {
      throw InputError(t.data_label() + ": axis " + (a == 0 ? "x" : "y") + ": " +
                       errors[static_cast<std::size_t>(a)]);
    }
  }
  for (int a = 0; a < 2; ++a) {
    for (const auto& w : res->axes[static_cast<std::size_t>(a)].warnings) {
      out.warnings.push_back(std::string("axis ") + (a == 0 ? "x" : "y") + ": " + w);
    }
  }
  out.result = std::move(res);
  out.status.succeed();
}

void SifsCutKind::publish(const TestOutcome& out, CampaignValues& values) const {
  const auto& r = out.result_of<SifsCutResult>();
  auto sum = std::make_shared<SifsCutSummary>();
  sum->id = out.spec->id;
  sum->spindle_rpm = r.spindle_rpm;
  for (std::size_t a = 0; a < 2; ++a) {
    sum->tap_exponent[a] = r.axes[a].q_exponent;
    sum->cut_exponent[a] = r.axes[a].cut_curve.summary.ok() ? r.axes[a].cut_curve.best_exponent : 0;
  }
  values.put(value::kSifsCutSummary, out.spec->id,
             std::shared_ptr<const SifsCutSummary>(std::move(sum)));
}

std::string sifs_compensated_path(const std::string& test_id) {
  return (test_id.empty() ? std::string(".") : test_id) + "/compensated.csv";
}

json SifsCutKind::results(const TestOutcome& out) const {
  const auto& r = out.result_of<SifsCutResult>();
  const auto& s = out.spec->kind_spec<SifsCutSpec>();
  json axes = json::object();
  for (std::size_t a = 0; a < 2; ++a) {
    const SifsAxisResult& ax = r.axes[a];
    json ub = json::array();
    for (std::size_t i = 0; i < ax.unbalance.harmonics.size(); ++i) {
      const auto c = ax.unbalance.c(static_cast<Eigen::Index>(i));
      ub.push_back({{"h", ax.unbalance.harmonics[i]},
                    {"amp_N", std::abs(c)},
                    {"phase_deg", std::arg(c) * kRadToDeg}});
    }
    json hs = json::array();
    for (std::size_t i = 0; i < ax.harmonics.size(); ++i) {
      const Eigen::Index k = static_cast<Eigen::Index>(i);
      json h = {{"h", ax.harmonics[i]},
                {"freq_hz", ax.harmonics[i] * r.spindle_hz},
                {"measured_amp_N", std::abs(ax.c_measured(k))},
                {"compensated_amp_N", std::abs(ax.c_compensated(k))}};
      if (r.has_reference) {
        const auto cr = ax.c_reference(k);
        h["reference_amp_N"] = std::abs(cr);
        const double ra = std::abs(cr);
        h["amp_err_pct"] =
            number_or_null(ra > 0 ? 100 * (std::abs(ax.c_compensated(k)) - ra) / ra : kNaN);
        h["measured_amp_err_pct"] =
            number_or_null(ra > 0 ? 100 * (std::abs(ax.c_measured(k)) - ra) / ra : kNaN);
        h["phase_err_deg"] = number_or_null(ra > 0 ? phase_err_deg(ax.c_compensated(k), cr) : kNaN);
        h["measured_phase_err_deg"] =
            number_or_null(ra > 0 ? phase_err_deg(ax.c_measured(k), cr) : kNaN);
      }
      hs.push_back(h);
    }
    json e = {
        {"q", ax.q},
        {"q_exponent", ax.q_exponent},
        {"r_N", ax.r_cut_n},
        {"r_tap_N", ax.r_tap_n},
        {"gain", sifs::to_string(s.gain)},
        {"tap_rmse_curve_N", to_vector(ax.tap_curve.rmse_n)},
        {"unbalance", ub},
        {"offset_N", ax.unbalance.c0},
        {"harmonics", hs},
        {"bandwidth_hz",
         {{"before", ax.bandwidth_before_hz}, {"after", number_or_null(ax.bandwidth_after_hz)}}},
        {"gain_converged_s", number_or_null(ax.gain_converged_s)},
        {"cond_F", ax.cond_F},
        {"obsv_rcond", ax.obsv_rcond}};
    if (r.has_reference) {
      e["spectral_rmse_N"] = {{"compensated", ax.rmse_compensated_n},
                              {"measured", ax.rmse_measured_n}};
      if (ax.cut_curve.summary.ok()) {
        e["cut_rmse_curve_N"] = to_vector(ax.cut_curve.rmse_n);
        e["cut_optimum_q_exponent"] = ax.cut_curve.best_exponent;
      }
    } else {
      e["spectral_rmse_N"] = nullptr;
    }
    axes[a == 0 ? "x" : "y"] = e;
  }
  return {{"spindle_rpm", r.spindle_rpm},
          {"tooth_passing_hz", r.tooth_passing_hz},
          {"filter_rate_hz", r.filter_rate_hz},
          {"teeth_count", r.teeth},
          {"compensated_file", sifs_compensated_path(out.spec->id)},
          {"axes", axes}};
}

void SifsCutKind::write_files(const TestOutcome& out,
                              const std::filesystem::path& report_dir) const {
  const auto& r = out.result_of<SifsCutResult>();
  const std::filesystem::path file = report_dir / sifs_compensated_path(out.spec->id);
  std::filesystem::create_directories(file.parent_path());
  std::ofstream o = open_for_writing(file);
  o << "t,fx,fy\n";
  const Eigen::VectorXd& x = r.axes[0].compensated_n;
  const Eigen::VectorXd& y = r.axes[1].compensated_n;
  char buf[96];
  for (Eigen::Index k = 0; k < std::min(x.size(), y.size()); ++k) {
    std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g\n", static_cast<double>(k) / r.filter_rate_hz,
                  x(k), y(k));
    o << buf;
  }
  close_checked(o, file);
}

json SifsCutKind::settings(const CampaignSpec& c) const {
  json tests = json::object();
  for (const auto& t : c.tests) {
    if (t.kind != name() || !t.usable()) continue;
    const auto* s = dynamic_cast<const SifsCutSpec*>(t.params.get());
    if (!s) continue;
    const double fr = s->filter_rate_hz.value_or(t.sample_rate_hz);
    tests[t.id.empty() ? "." : t.id] = {
        {"filter_rate_hz", fr},
        {"band_hz",
         {s->band_hz ? s->band_hz->first : 0.0, s->band_hz ? s->band_hz->second : 0.4 * fr}},
        {"unbalance_harmonics", s->unbalance_harmonics},
        {"gain", sifs::to_string(s->gain)}};
  }
  const sifs::SweepOptions so;
  json d = {{"q_exponents", {so.n_first, so.n_last}},
            {"q_flat_tolerance_ratio", so.flat_tolerance},
            {"process_noise", "Q_c = q I_2 on (w_dc, w_ac); R = the RMS in N, used as a variance"},
            {"discretisation", "Van Loan"}};
  if (!tests.empty()) d["tests"] = tests;
  return d;
}

std::string SifsCutKind::note(const TestOutcome& out) const {
  const auto& r = out.result_of<SifsCutResult>();
  std::string n = fmt_sig(r.spindle_rpm, 5) + " rpm, q = 2^" +
                  std::to_string(r.axes[0].q_exponent) + " / 2^" +
                  std::to_string(r.axes[1].q_exponent);
  if (r.has_reference) {
    n += ", RMSE x " + fmt_sig(r.axes[0].rmse_measured_n, 3) + " -> " +
         fmt_sig(r.axes[0].rmse_compensated_n, 3) + " N";
  }
  return n;
}

namespace {

// Element i of a truth.yaml list as a number, NaN when absent or not a number.
double truth_element(const YAML::Node& list, std::size_t i) {
  if (!list.IsSequence() || i >= list.size()) return std::nan("");
  try {
    return list[i].as<double>();
  } catch (const YAML::Exception&) {
    return std::nan("");
  }
}

}  // namespace

void SifsCutKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                                TruthComparison& c) const {
  const auto& r = out.result_of<SifsCutResult>();
  const YAML::Node& v = *in.entry;
  const std::string& id = out.spec->id;
  const char* axes[2] = {"x", "y"};
  // Unbalance amplitudes.
  if (const YAML::Node ub = v["unbalance"]) {
    for (int a = 0; a < 2; ++a) {
      const YAML::Node list = ub[axes[a]];
      if (!list || !list.IsSequence()) continue;
      const auto& fit = r.axes[static_cast<std::size_t>(a)].unbalance;
      for (const auto& e : list) {
        const double h = truth_number(e, "h");
        for (std::size_t i = 0; i < fit.harmonics.size(); ++i) {
          if (fit.harmonics[i] != h) continue;
          add_truth_row(c,
                        std::string("unbalance.") + axes[a] + ".h" +
                            std::to_string(fit.harmonics[i]) + ".amp_N",
                        id, truth_number(e, "amp_N"),
                        std::abs(fit.c(static_cast<Eigen::Index>(i))));
        }
      }
    }
  }
  // Compensated harmonic amplitudes against the true tip force's (the first three analysed).
  if (const YAML::Node hs = v["harmonics"]) {
    const YAML::Node hl = hs["h"];
    if (hl && hl.IsSequence()) {
      for (int a = 0; a < 2; ++a) {
        const YAML::Node re = hs[std::string(axes[a]) + "_re_N"];
        const YAML::Node im = hs[std::string(axes[a]) + "_im_N"];
        if (!re || !im) continue;
        const auto& ax = r.axes[static_cast<std::size_t>(a)];
        int shown = 0;
        for (std::size_t i = 0; i < hl.size() && shown < 3; ++i) {
          // truth.yaml values that are no whole harmonic or no number compare with nothing
          // (never an exception: truth_number gives NaN for them).
          const double hv = truth_element(hl, i);
          if (!(std::abs(hv) <= 1000) || hv != std::floor(hv)) continue;
          const int h = static_cast<int>(hv);
          for (std::size_t k = 0; k < ax.harmonics.size(); ++k) {
            if (ax.harmonics[k] != h || h % std::max(1, r.teeth) != 0) continue;
            const double amp = std::hypot(truth_element(re, i), truth_element(im, i));
            add_truth_row(c,
                          std::string("harmonic.") + axes[a] + ".h" + std::to_string(h) +
                              ".compensated_amp_N",
                          id, amp, std::abs(ax.c_compensated(static_cast<Eigen::Index>(k))));
            ++shown;
          }
        }
      }
    }
  }
}

std::shared_ptr<const KindSpec> SifsCutKind::parse_synth(const YAML::Node& section,
                                                         const SynthContext& ctx,
                                                         YamlReader& r) const {
  return parse_sifs_synth(section, ctx, r);
}

int SifsCutKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  return write_sifs_synth(section, ctx);
}

// ---- the per-test cache (app/core/archive.h) -------------------------------------------------

template <class Ar>
void fields(Ar& ar, SifsAxisResult& a) {
  LAYOUT_GUARD(SifsAxisResult, 848);
  ar(a.summary, a.unbalance, a.r_cut_n, a.r_tap_n, a.tap_curve, a.q, a.q_exponent, a.harmonics,
     a.c_measured, a.c_compensated, a.c_reference, a.rmse_compensated_n, a.rmse_measured_n,
     a.cut_curve, a.bandwidth_before_hz, a.bandwidth_after_hz, a.cond_F, a.obsv_rcond,
     a.gain_converged_s, a.warnings, a.measured_n, a.compensated_n, a.reference_n);
}

template <class Ar>
void fields(Ar& ar, SifsCutResult& r) {
  LAYOUT_GUARD(SifsCutResult, 1768);
  ar(r.spindle_rpm, r.tooth_passing_hz, r.spindle_hz, r.fs_hz, r.filter_rate_hz, r.teeth,
     r.has_reference, r.axes, r.cut_begin, r.cut_end);
}

std::string SifsCutKind::save(const TestOutcome& out) const {
  return save_result<SifsCutResult>(out);
}

void SifsCutKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<SifsCutResult>(bytes, out);
}

}  // namespace chatterlab::app
