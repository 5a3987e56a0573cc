// Kind `sweep-frf` (format section 5): the spindle drive's torque-to-current FRF from a
// speed-loop sine sweep (001 sec. 3.1), realized by ERA (001 sec. 3.2). See sysid_kinds.h and
// docs/sysid.md.
#include <cmath>

#include "analysis/signal/welch.h"
#include "app/core/format.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/sysid/sysid_archive.h"
#include "app/kinds/sysid/sysid_kinds.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {
const std::vector<std::string> kSweepChannels = {"speed_ref", "speed", "current", "current_act"};
}  // namespace

SweepFrfs sweep_frfs(const Eigen::VectorXd& speed_ref, const Eigen::VectorXd& speed,
                     const Eigen::VectorXd& current, const Eigen::VectorXd& current_act,
                     double fs_hz, int segment, double Kt, double band_lo_hz, double band_hi_hz) {
  const Eigen::VectorXd e = speed_ref - speed;
  const signal::CrossSpectra s =
      signal::welch_cross_spectra(speed_ref, {e, speed, current, current_act}, segment, fs_hz);
  SweepFrfs out;
  out.segments = s.segments;
  out.f_hz = s.f_hz;
  const auto& S_re = s.S_rx[0];
  const auto& S_rs = s.S_rx[1];
  const auto& S_rc = s.S_rx[2];
  const auto& S_ra = s.S_rx[3];
  out.G_o = S_rs.cwiseQuotient(S_re);
  out.G_loop = S_rs.cwiseQuotient(S_rc);
  out.G_s = S_rs.cwiseQuotient(S_ra);
  out.G_dtau = (S_rs.array() * S_rc.array() / (Kt * S_ra.array() * s.S_rr.array())).matrix();
  const auto coherence = [&](int c) {
    return (s.S_rx[static_cast<std::size_t>(c)].cwiseAbs2().array() /
            (s.S_rr.array() * s.S_xx[static_cast<std::size_t>(c)].array()))
        .matrix()
        .eval();
  };
  out.coh_speed = coherence(1);
  out.coh_current = coherence(2);
  out.coh_current_act = coherence(3);
  out.band_begin = out.f_hz.size();
  out.band_end = 0;
  for (Eigen::Index k = 0; k < out.f_hz.size(); ++k) {
    if (out.f_hz[k] > 0.0 && out.f_hz[k] >= band_lo_hz && out.f_hz[k] <= band_hi_hz) {
      out.band_begin = std::min(out.band_begin, k);
      out.band_end = k + 1;
    }
  }
  if (out.band_end <= out.band_begin) out.band_begin = out.band_end = 0;
  return out;
}

std::vector<std::string> SweepFrfKind::keys() const {
  return {"spindle_rpm", "sweep_band_hz", "torque_constant_Nm_per_A", "segment_samples",
          "era_max_order"};
}

std::shared_ptr<const KindSpec> SweepFrfKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto s = std::make_shared<SweepFrfSpec>();
  if (const auto v = r.optional_double(root, "spindle_rpm")) {
    if (!(*v >= 0.0)) r.error("spindle_rpm", "must be >= 0");
    s->spindle_rpm = *v;
  }
  const double rate = root["sample_rate_hz"] && root["sample_rate_hz"].IsScalar()
                          ? root["sample_rate_hz"].as<double>(0.0)
                          : 0.0;
  if (const auto b = r.optional_pair(root, "sweep_band_hz")) {
    s->band_lo_hz = b->first;
    s->band_hi_hz = b->second;
    if (!(b->first >= 0.0 && b->second > b->first)) {
      r.error("sweep_band_hz", "must be [low, high] with 0 <= low < high");
    } else if (rate > 0.0 && b->second > 0.5 * rate) {
      r.error("sweep_band_hz", "high = " + fmt_sig(b->second, 6) +
                                   " Hz is above half the sample rate (" + fmt_sig(0.5 * rate, 6) +
                                   " Hz)");
    }
  } else if (!root["sweep_band_hz"]) {
    r.error("sweep_band_hz", "is required: [low, high] Hz, the excited band");
  }
  s->torque_constant_Nm_per_A = r.required_double(root, "torque_constant_Nm_per_A");
  if (!(s->torque_constant_Nm_per_A > 0.0) && !std::isnan(s->torque_constant_Nm_per_A)) {
    r.error("torque_constant_Nm_per_A", "must be > 0");
  }
  if (const auto n = r.optional_int(root, "segment_samples", "", 64, 1 << 22)) {
    if (*n % 2 != 0) r.error("segment_samples", "must be even");
    s->segment_samples = static_cast<int>(*n);
  }
  if (const auto n = r.optional_int(root, "era_max_order", "", 1, 1000)) {
    s->era_max_order = static_cast<int>(*n);
  }
  return s;
}

std::vector<std::string> SweepFrfKind::required_channels(const TestSpec&) const {
  return kSweepChannels;
}

std::vector<std::string> SweepFrfKind::check_record(const TestSpec& t, double duration_s) const {
  const auto& s = t.kind_spec<SweepFrfSpec>();
  const double samples = duration_s * t.sample_rate_hz;
  if (samples + 0.5 < s.segment_samples) {
    return {t.yaml_label + ": key 'segment_samples' " + std::to_string(s.segment_samples) +
            " is longer than the record (" + fmt_sig(samples, 8) + " samples)"};
  }
  return {};
}

std::vector<std::string> SweepFrfKind::provides(const TestSpec& t) const {
  return {value::drive_model(t.id)};
}

std::string SweepFrfKind::describe_value(const std::string& name) const {
  return value::describe_drive_model(name);
}

void SweepFrfKind::run(const TestSpec& t, const CampaignValues&, const RunContext&,
                       TestOutcome& out) const {
  const auto& s = t.kind_spec<SweepFrfSpec>();
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  Eigen::VectorXd ch[4];
  for (int i = 0; i < 4; ++i) {
    const std::string& n = kSweepChannels[static_cast<std::size_t>(i)];
    ch[i] = table.channel(n, t.channel(n));
  }
  auto res = std::make_unique<SweepFrfResult>();
  try {
    res->frfs = sweep_frfs(ch[0], ch[1], ch[2], ch[3], t.sample_rate_hz, s.segment_samples,
                           s.torque_constant_Nm_per_A, s.band_lo_hz, s.band_hi_hz);
  } catch (const InputError& e) {
    throw InputError(label + ": " + e.what());
  }
  const SweepFrfs& F = res->frfs;
  const Eigen::Index nb = F.band_end - F.band_begin;
  if (nb < 4) {
    out.status.fail(label + ": sweep_band_hz holds " + std::to_string(nb) +
                    " Welch points (segment_samples " + std::to_string(s.segment_samples) +
                    "); at least 4 are needed");
    return;
  }
  // The band's points plus (0 Hz, 1/Kt): integral speed control makes the static
  // torque-to-current gain 1/Kt exactly (format section 5).
  Eigen::VectorXd f(nb + 1);
  Eigen::VectorXcd G(nb + 1);
  f[0] = 0.0;
  G[0] = 1.0 / s.torque_constant_Nm_per_A;
  f.tail(nb) = F.f_hz.segment(F.band_begin, nb);
  G.tail(nb) = F.G_dtau.segment(F.band_begin, nb);
  for (Eigen::Index k = 0; k < G.size(); ++k) {
    if (!std::isfinite(G[k].real()) || !std::isfinite(G[k].imag())) {
      out.status.fail(label + ": the torque-to-current FRF is not finite at " + fmt_sig(f[k], 6) +
                      " Hz (a channel without signal there: check sweep_band_hz)");
      return;
    }
  }
  res->min_coherence_in_band = 1.0;
  for (Eigen::Index k = F.band_begin; k < F.band_end; ++k) {
    res->min_coherence_in_band = std::min(
        {res->min_coherence_in_band, F.coh_speed[k], F.coh_current[k], F.coh_current_act[k]});
  }
  sysid::EraOptions o;
  o.max_order = s.era_max_order;
  o.grid_step_hz = t.sample_rate_hz / s.segment_samples;
  res->model = run_era_model(t, f, G, "N*m", "A", o);
  const auto& e = res->model.era;
  out.warnings.insert(out.warnings.end(), e.summary.warnings.begin(), e.summary.warnings.end());
  if (res->min_coherence_in_band < 0.5) {
    out.warnings.push_back("coherence with the speed command falls to " +
                           fmt_sig(res->min_coherence_in_band, 3) +
                           " inside sweep_band_hz: the FRF is noisy there");
  }
  if (!e.summary.ok()) {
    out.status.fail(label + ": " + e.summary.message);
    return;
  }
  out.result = std::move(res);
  out.status.succeed();
}

template <class Ar>
void fields(Ar& ar, SweepFrfs& f) {
  LAYOUT_GUARD(SweepFrfs, 152);
  ar(f.f_hz, f.G_o, f.G_loop, f.G_s, f.G_dtau, f.coh_speed, f.coh_current, f.coh_current_act,
     f.segments, f.band_begin, f.band_end);
}

template <class Ar>
void fields(Ar& ar, SweepFrfResult& r) {
  LAYOUT_GUARD(SweepFrfResult, 760);
  ar(r.frfs, r.model, r.min_coherence_in_band);
}

std::string SweepFrfKind::save(const TestOutcome& out) const {
  return save_result<SweepFrfResult>(out);
}

void SweepFrfKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<SweepFrfResult>(bytes, out);
}

void SweepFrfKind::publish(const TestOutcome& out, CampaignValues& values) const {
  values.put(value::drive_model(out.spec->id), out.spec->id,
             out.result_of<SweepFrfResult>().model.drive);
}

json SweepFrfKind::results(const TestOutcome& out) const {
  const auto& r = out.result_of<SweepFrfResult>();
  const auto& s = out.spec->kind_spec<SweepFrfSpec>();
  json j = era_model_json(r.model);
  j["frf"] = {{"segment_samples", s.segment_samples},
              {"segments", r.frfs.segments},
              {"band_hz", {s.band_lo_hz, s.band_hi_hz}},
              {"points", r.frfs.band_end - r.frfs.band_begin},
              {"min_coherence", r.min_coherence_in_band}};
  j["spindle_rpm"] = s.spindle_rpm;
  j["torque_constant_Nm_per_A"] = s.torque_constant_Nm_per_A;
  return j;
}

std::string SweepFrfKind::note(const TestOutcome& out) const {
  return era_model_note(out.result_of<SweepFrfResult>().model);
}

render::Figure sweep_loop_figure(const SweepFrfResult& r) {
  const SweepFrfs& F = r.frfs;
  std::vector<double> x, go, gl, gs, c1, c2, c3;
  // On the log frequency axis, about 400 points spaced evenly in log f draw the same curves as
  // every Welch bin (the high decades hold most bins); this keeps the figure light.
  double next = 0.0;
  const double step = F.band_end > F.band_begin + 1
                          ? std::pow(F.f_hz[F.band_end - 1] / F.f_hz[F.band_begin], 1.0 / 400.0)
                          : 2.0;
  for (Eigen::Index k = F.band_begin; k < F.band_end; ++k) {
    if (F.f_hz[k] < next) continue;
    next = F.f_hz[k] * step;
    x.push_back(F.f_hz[k]);
    go.push_back(std::abs(F.G_o[k]));
    gl.push_back(std::abs(F.G_loop[k]));
    gs.push_back(std::abs(F.G_s[k]));
    c1.push_back(F.coh_speed[k]);
    c2.push_back(F.coh_current[k]);
    c3.push_back(F.coh_current_act[k]);
  }
  render::Figure fig;
  fig.height_in = 4.6;
  fig.share_x = true;
  render::Axes& a = fig.panels.emplace_back();
  a.y_label = "|G|";
  a.log_y = true;
  a.log_x = true;
  a.relative_height = 2;
  a.series = {{x, go, "G_o, speed loop gain (3.4)", render::SeriesStyle::kLine, "#0072B2"},
              {x, gl, "G_loop, speed / current (3.5)", render::SeriesStyle::kLine, "#D55E00"},
              {x, gs, "G_s, speed / actual current (3.6)", render::SeriesStyle::kLine, "#009E73"}};
  render::Axes& c = fig.panels.emplace_back();
  c.x_label = "frequency [Hz]";
  c.y_label = "coherence";
  c.log_x = true;
  c.y_range = render::Range{0, 1.05};
  c.series = {{x, c1, "speed", render::SeriesStyle::kLine, "#0072B2"},
              {x, c2, "current", render::SeriesStyle::kLine, "#D55E00"},
              {x, c3, "actual current", render::SeriesStyle::kLine, "#009E73"}};
  return fig;
}

void SweepFrfKind::figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const {
  const auto& r = out.result_of<SweepFrfResult>();
  const std::string stem = figure_stem("sweep-frf", out.spec->id);
  jobs.add(out.spec->id, "frf", stem + "frf", era_frf_figure(r.model));
  jobs.add(out.spec->id, "singular-values", stem + "sv", era_singular_value_figure(r.model));
  jobs.add(out.spec->id, "loops", stem + "loops", sweep_loop_figure(r));
}

json SweepFrfKind::report_section(const CampaignResults&, const std::vector<const TestOutcome*>& ok,
                                  const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) {
    const auto& r = t->result_of<SweepFrfResult>();
    const auto& s = t->spec->kind_spec<SweepFrfSpec>();
    json j = era_model_section(*t, r.model, figures);
    j["spindle_rpm"] = fmt_sig(s.spindle_rpm, 5);
    j["band"] = fmt_sig(s.band_lo_hz, 4) + "&ndash;" + fmt_sig(s.band_hi_hz, 5);
    j["points"] = r.frfs.band_end - r.frfs.band_begin;
    j["segments"] = r.frfs.segments;
    j["segment_samples"] = s.segment_samples;
    j["kt"] = fmt_sig(s.torque_constant_Nm_per_A, 4);
    j["min_coherence"] = fmt_sig(r.min_coherence_in_band, 3);
    j["figure_loops"] = figures.of(t->spec->id, "loops");
    tests.push_back(j);
  }
  return {{"toc", json::array({{{"anchor", "sweep-frf"},
                                {"title", "Spindle drive models from sweeps (ERA)"}}})},
          {"sweep_tests", tests}};
}

void SweepFrfKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                                 TruthComparison& c) const {
  era_model_truth(in, out, out.result_of<SweepFrfResult>().model, c);
}

}  // namespace chatterlab::app
