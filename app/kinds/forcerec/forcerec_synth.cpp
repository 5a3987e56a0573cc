// The synth section `forcerec` (docs/format/synth-spec.md): dyno-frf hammer tests of a table
// dynamometer whose axes are 004 Table 3.1's models; with `cuts.drift`, also hammer tests of the
// first-pass models (Table 3.1 frequency-scaled); the cut records of `cuts` are written by
// forcerec_cut_synth.cpp.
//
// Each hit is a half-sine force pulse with a weaker bounce a few milliseconds later (a hit and
// its bounce are one hit, format section 4). The dynamometer's output is the continuous model
// driven by the continuous pulse: the force is evaluated at 16 times the record's rate and the
// model discretized there (zero-order hold over 1/16 of a sample), then both are sampled at the
// record's rate. The test's own method (H1 and a fit in continuous time) therefore sees the
// physics, not the discretization it would invert (no inverse crime, notes/004.md sec. 9 item 4).
#include "app/kinds/forcerec/forcerec_synth.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string_view>
#include <tuple>

#include "analysis/common/check.h"
#include "analysis/common/constants.h"
#include "analysis/forcerec/model.h"
#include "analysis/forcerec/transfer_fit.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/forcerec/forcerec_kinds.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

namespace forcerec_synth {

const Table31Axis& table31_axis(char axis) {
  const auto it = std::find_if(kTable31.begin(), kTable31.end(),
                               [axis](const Table31Axis& t) { return t.axis == axis; });
  CHATTERLAB_CHECK(it != kTable31.end(), "Table 3.1 has axes x, y and z only");
  return *it;
}

forcerec::TransferModel table31_model(char axis) {
  const Table31Axis& tab = table31_axis(axis);
  const Eigen::Map<const Eigen::VectorXd> num(tab.num.data(), 6), den(tab.den.data(), 6);
  return forcerec::transfer_model_from_coefficients(num, den);
}

forcerec::TransferModel frequency_scaled(const forcerec::TransferModel& model, double scale) {
  return forcerec::transfer_model_from_roots(model.poles() * scale, model.zeros() * scale,
                                             model.b1 * scale);
}

forcerec::DiscreteModel oversampled_model(const forcerec::TransferModel& model,
                                          double sample_rate_hz) {
  return forcerec::zoh(forcerec::realize_scaled_modal(model),
                       sample_rate_hz * static_cast<double>(kOversampling));
}

}  // namespace forcerec_synth

namespace {

using forcerec_synth::ForcerecSynthSpec;
using forcerec_synth::kOversampling;

void read(YamlReader& r, const YAML::Node& n, const std::string& key, double& out) {
  out = r.optional_double(n, key, "forcerec").value_or(out);
}
void positive(YamlReader& r, const std::string& key, double v) {
  if (!(v > 0) || !std::isfinite(v)) r.error("forcerec." + key, "must be > 0");
}

// Half-sine pulse of duration d and peak p starting at t0, at time t.
double half_sine(double t, double t0, double d, double p) {
  const double u = t - t0;
  return u >= 0.0 && u < d ? p * std::sin(kPi * u / d) : 0.0;
}

// Writes the dyno-frf hammer test `id` of one axis whose dynamometer is `model` (coefficients
// num, den for truth.yaml), noise from stream (tag, axis), and its truth entry.
void write_hammer_test(const ForcerecSynthSpec& s, char axis, const forcerec::TransferModel& model,
                       const std::vector<double>& num_coefficients,
                       const std::vector<double>& den_coefficients, const std::string& id,
                       std::string_view stream_tag, const std::string& source, SynthContext& ctx) {
  const forcerec::DiscreteModel fine = forcerec_synth::oversampled_model(model, s.fs_hz);
  // The record: 0.2 s before the first hit, hit_spacing_s between hits and after the last.
  const double first_s = 0.2;
  const double duration_s = first_s + s.hits * s.hit_spacing_s;
  const Eigen::Index n = static_cast<Eigen::Index>(std::llround(duration_s * s.fs_hz));
  Eigen::VectorXd hammer(n), dyno(n);
  std::mt19937_64 rng(ctx.stream_seed(stream_tag, static_cast<std::uint64_t>(axis)));
  std::normal_distribution<double> noise(0.0, s.noise_N);
  // The hammer force at time t: the pulse of the hit whose slot holds t, and its bounce.
  const auto force_at = [&s, first_s](double t) {
    const double slot = std::floor((t - first_s) / s.hit_spacing_s);
    if (slot < 0.0 || slot >= s.hits) return 0.0;
    const double t0 = first_s + slot * s.hit_spacing_s;
    return half_sine(t, t0, s.pulse_s, s.peak_N) +
           half_sine(t, t0 + s.bounce_delay_s, s.pulse_s, s.bounce_fraction * s.peak_N);
  };
  Eigen::VectorXd x = Eigen::VectorXd::Zero(fine.order());
  const double dt = 1.0 / (s.fs_hz * kOversampling);
  for (Eigen::Index k = 0; k < n; ++k) {
    hammer[k] = force_at(static_cast<double>(k) / s.fs_hz);
    dyno[k] = fine.C.dot(x);
    for (int j = 0; j < kOversampling; ++j) {
      // Each fine step holds the force at its mid-point (the half-sine is smooth).
      const double t = (static_cast<double>(k * kOversampling + j) + 0.5) * dt;
      x = fine.Ad * x + fine.Bd * force_at(t);
    }
  }
  for (Eigen::Index k = 0; k < n; ++k) {
    hammer[k] = (hammer[k] + noise(rng)) / s.hammer_scale_N_per_V;
    dyno[k] = (dyno[k] + noise(rng)) / s.dyno_scale_N_per_V;
  }
  const std::string axis_name(1, axis);
  const auto dir = ctx.out / id;
  std::filesystem::create_directories(dir);
  write_signals(dir / "hits.f32", {"hammer", "dyno"}, {&hammer, &dyno});
  YAML::Emitter y;
  configure_synth_emitter(y);
  y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "dyno-frf";
  y << YAML::Key << "axis" << YAML::Value << axis_name;
  y << YAML::Key << "sample_rate_hz" << YAML::Value << synth_number(s.fs_hz);
  y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
    << YAML::Value << "hits.f32" << YAML::Key << "channels" << YAML::Value << YAML::Flow
    << YAML::BeginSeq << "hammer"
    << "dyno" << YAML::EndSeq << YAML::EndMap;
  y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "hammer" << YAML::Value << synth_numbers({{"scale", s.hammer_scale_N_per_V}});
  y << YAML::Key << "dyno" << YAML::Value << synth_numbers({{"scale", s.dyno_scale_N_per_V}});
  y << YAML::EndMap;
  y << YAML::Key << "hits" << YAML::Value << "auto";
  y << YAML::Key << "band_hz" << YAML::Value << synth_number_list({s.band_lo_hz, s.band_hi_hz});
  y << YAML::Key << "order" << YAML::Value << 6 << YAML::EndMap;
  write_synth_yaml(dir / "test.yaml", y);

  YAML::Node e(YAML::NodeType::Map);
  e["axis"] = axis_name;
  e["order"] = 6;
  e["band_hz"] = synth_number_list({s.band_lo_hz, s.band_hi_hz});
  e["dc_gain"] = synth_number(forcerec::dc_gain(model));
  e["gain_1_s"] = synth_number(model.b1);
  YAML::Node modes(YAML::NodeType::Sequence), zeros(YAML::NodeType::Sequence);
  for (const auto& p : model.pole_pairs) {
    modes.push_back(synth_numbers({{"fn_hz", p.fn_hz}, {"zeta", p.zeta}}));
  }
  for (const auto& z : model.zero_pairs) {
    zeros.push_back(synth_numbers({{"fn_hz", z.fn_hz}, {"zeta", z.zeta}}));
  }
  e["modes"] = modes;
  e["zeros"] = zeros;
  e["real_zeros_rad_s"] = synth_number_list(model.real_zeros_rad_s);
  e["num"] = synth_number_list(num_coefficients);
  e["den"] = synth_number_list(den_coefficients);
  e["source"] = source;
  ctx.truth.tests[id] = e;
}

}  // namespace

std::shared_ptr<const KindSpec> DynoFrfKind::parse_synth(const YAML::Node& section,
                                                         const SynthContext& ctx,
                                                         YamlReader& r) const {
  auto s = std::make_shared<ForcerecSynthSpec>();
  if (!section.IsMap() && !section.IsNull()) {
    r.error("forcerec", "must be a mapping (docs/format/synth-spec.md)");
    return s;
  }
  const YAML::Node n = section.IsMap() ? section : YAML::Node(YAML::NodeType::Map);
  r.check_keys(n,
               {"folder", "sample_rate_hz", "axes", "hits", "hit_spacing_s", "peak_N", "pulse_s",
                "bounce_fraction", "bounce_delay_s", "noise_N", "band_hz", "cuts"},
               "forcerec");
  s->folder = read_synth_folder(n, "forcerec", s->folder, r);
  read(r, n, "sample_rate_hz", s->fs_hz);
  if (n["axes"]) {
    s->axes.clear();
    for (const std::string& a : r.string_list(n, "axes", true, "forcerec")) {
      if (a != "x" && a != "y" && a != "z") {
        r.error("forcerec.axes", "every axis must be x, y or z, not '" + a + "'");
      } else if (std::find(s->axes.begin(), s->axes.end(), a[0]) != s->axes.end()) {
        r.error("forcerec.axes", "axis " + a + " is listed twice");
      } else {
        s->axes.push_back(a[0]);
      }
    }
  }
  if (auto h = r.optional_int(n, "hits", "forcerec", 1, 100)) s->hits = static_cast<int>(*h);
  read(r, n, "hit_spacing_s", s->hit_spacing_s);
  read(r, n, "peak_N", s->peak_N);
  read(r, n, "pulse_s", s->pulse_s);
  read(r, n, "bounce_fraction", s->bounce_fraction);
  read(r, n, "bounce_delay_s", s->bounce_delay_s);
  read(r, n, "noise_N", s->noise_N);
  if (const auto b = r.optional_pair(n, "band_hz", "forcerec")) {
    std::tie(s->band_lo_hz, s->band_hi_hz) = *b;
  }
  positive(r, "sample_rate_hz", s->fs_hz);
  positive(r, "peak_N", s->peak_N);
  positive(r, "pulse_s", s->pulse_s);
  if (!(s->noise_N >= 0.0)) r.error("forcerec.noise_N", "must be >= 0");
  if (!(s->bounce_fraction >= 0.0 && s->bounce_fraction < 1.0)) {
    r.error("forcerec.bounce_fraction", "must be in [0, 1)");
  }
  if (!(s->bounce_delay_s >= s->pulse_s && s->bounce_delay_s < 0.02)) {
    r.error("forcerec.bounce_delay_s", "must be at least pulse_s and below 0.02 s");
  }
  if (!(s->hit_spacing_s >= 0.1 && s->hit_spacing_s * s->hits <= 600.0)) {
    r.error("forcerec.hit_spacing_s", "must be >= 0.1 s, and hits x spacing at most 600 s");
  }
  if (!(s->band_lo_hz >= 0.0 && s->band_hi_hz > s->band_lo_hz && s->band_hi_hz <= 0.5 * s->fs_hz)) {
    r.error("forcerec.band_hz", "must be [lo, hi] with 0 <= lo < hi <= sample_rate_hz / 2");
  }
  if (n["cuts"]) forcerec_synth::parse_cuts(n["cuts"], ctx, *s, r);
  return s;
}

int DynoFrfKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  const auto& s = dynamic_cast<const ForcerecSynthSpec&>(section);
  int written = 0;
  for (char axis : s.axes) {
    const std::string axis_name(1, axis);
    const forcerec_synth::Table31Axis& tab = forcerec_synth::table31_axis(axis);
    write_hammer_test(s, axis, forcerec_synth::table31_model(axis),
                      std::vector<double>(tab.num.begin(), tab.num.end()),
                      std::vector<double>(tab.den.begin(), tab.den.end()),
                      s.folder + "/hammer/" + axis_name, "synth.forcerec.hammer",
                      "004 Table 3.1, H" + axis_name + axis_name, ctx);
    ++written;
  }
  if (!s.cuts) return written;
  if (const auto scale = s.cuts->drift_fn_scale) {
    for (char axis : s.axes) {
      const std::string axis_name(1, axis);
      const forcerec::TransferModel drifted =
          forcerec_synth::frequency_scaled(forcerec_synth::table31_model(axis), *scale);
      const Eigen::VectorXd num = forcerec::numerator_coefficients(drifted);
      const Eigen::VectorXd den = forcerec::denominator_coefficients(drifted);
      write_hammer_test(s, axis, drifted, std::vector<double>(num.data(), num.data() + num.size()),
                        std::vector<double>(den.data(), den.data() + den.size()),
                        s.folder + "/hammer-before/" + axis_name, "synth.forcerec.hammer-before",
                        "004 Table 3.1, H" + axis_name + axis_name +
                            ", every pole and zero frequency scaled by fn_scale = " +
                            synth_number(*scale) + " (G(s / fn_scale), DC gain kept)",
                        ctx);
      ++written;
    }
  }
  return written + forcerec_synth::write_cuts(s, ctx);
}

}  // namespace chatterlab::app
