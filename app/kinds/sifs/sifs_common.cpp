#include "app/kinds/sifs/sifs_common.h"

#include <cmath>

#include "analysis/signal/resample.h"
#include "app/core/format.h"
#include "app/kinds/sifs/sifs_kinds.h"

namespace chatterlab::app {

sifs::Axis read_sifs_axis(const YAML::Node& root, YamlReader& r, bool allow_z) {
  const std::string a = r.required_string(root, "axis");
  if (a == "x") return sifs::Axis::kX;
  if (a == "y") return sifs::Axis::kY;
  if (a == "z" && allow_z) return sifs::Axis::kZ;
  if (!a.empty())
    r.error("axis",
            std::string("must be x") + (allow_z ? ", y or z" : " or y") + ", not '" + a + "'");
  return sifs::Axis::kX;
}

sifs::Washers read_washers(const SignalTable& table, const TestSpec& t) {
  sifs::Washers w(static_cast<Eigen::Index>(table.samples()), 6);
  for (int i = 0; i < 6; ++i) {
    const std::string& n = kWasherChannels[static_cast<std::size_t>(i)];
    w.col(i) = table.channel(n, t.channel(n));
  }
  return w;
}

std::optional<double> read_tool_length(const YAML::Node& root, YamlReader& r) {
  const auto L = r.optional_double(root, "tool_length_mm");
  if (L && !(*L > 0)) {
    r.error("tool_length_mm", "must be > 0");
    return std::nullopt;
  }
  return L;
}

Eigen::Matrix3d SifsCalibration::at(const std::optional<double>& length_mm,
                                    std::string* note) const {
  if (by_length.empty()) {
    if (note && single_length_mm && length_mm &&
        std::abs(*single_length_mm - *length_mm) > 1e-9 * std::max(1.0, *length_mm)) {
      *note = "the static tests calibrate tool_length_mm " + fmt_sig(*single_length_mm, 6) +
              " only; that calibration is used for " + fmt_sig(*length_mm, 6) + " mm";
    }
    return C;
  }
  if (!length_mm) {
    std::string lengths;
    for (const auto& [L, m] : by_length) lengths += (lengths.empty() ? "" : ", ") + fmt_sig(L, 6);
    throw InputError("key 'tool_length_mm' is required: the static tests calibrate tool lengths " +
                     lengths + " mm");
  }
  for (const auto& [L, m] : by_length) {
    if (std::abs(L - *length_mm) <= 1e-9 * std::max(1.0, L)) return m;
  }
  if (note) {
    *note = "calibration at tool_length_mm " + fmt_sig(*length_mm, 6) +
            " from the tool-length law of the static tests (003 eq. 3-4, every entry)";
  }
  return slope_per_mm * *length_mm + intercept;
}

Eigen::Matrix3d calibration_for(const SifsCalibration& cal, const TestSpec& t,
                                const std::optional<double>& length_mm,
                                std::vector<std::string>& warnings) {
  std::string note;
  try {
    const Eigen::Matrix3d C = cal.at(length_mm, &note);
    if (!note.empty()) warnings.push_back(note);
    return C;
  } catch (const InputError& e) {
    throw InputError(t.yaml_label + ": " + e.what());
  }
}

sifs::TapSweepInput tap_sweep_input(const SifsTapData& tap, double filter_rate_hz,
                                    double band_lo_hz, double band_hi_hz, sifs::GainMode gain) {
  sifs::TapSweepInput in;
  in.modes = &tap.modes;
  in.filter_rate_hz = filter_rate_hz;
  in.r_tap_n = tap.r_tap_n;
  in.band_lo_hz = band_lo_hz;
  in.band_hi_hz = band_hi_hz;
  in.gain = gain;
  const double ratio = filter_rate_hz / tap.fs_hz;
  if (std::abs(ratio - 1.0) < 1e-12) {
    in.hammer_n = tap.hammer_n;
    in.response_n = tap.response_n;
  } else {
    const signal::RationalResampler rs(tap.fs_hz, filter_rate_hz);
    in.hammer_n = rs.apply(tap.hammer_n);
    in.response_n = rs.apply(tap.response_n);
  }
  const Eigen::Index n = in.hammer_n.size();
  Eigen::Index len = -1;
  for (const auto& w : tap.windows) {
    const Eigen::Index l = static_cast<Eigen::Index>(std::floor((w.end - w.begin) * ratio));
    len = len < 0 ? l : std::min(len, l);
  }
  const Eigen::Index guard = static_cast<Eigen::Index>(std::ceil(1e-3 * filter_rate_hz));
  for (std::size_t i = 0; i < tap.windows.size(); ++i) {
    const Eigen::Index b =
        static_cast<Eigen::Index>(std::llround(static_cast<double>(tap.windows[i].begin) * ratio));
    const Eigen::Index e = std::min(b + len, n);
    in.windows.push_back({b, e});
    const Eigen::Index impact =
        static_cast<Eigen::Index>(std::llround(static_cast<double>(tap.impact[i]) * ratio));
    in.pre_end.push_back(std::max<Eigen::Index>(1, impact - guard - b));
  }
  // R_tap at the filter rate: the RMS of the pooled pre-impact responses (each with its own mean
  // removed) of the record the filter sees, so that q/R means the same in the tap sweep and in
  // the cut, whose R is measured at the filter rate too (resampling to a lower rate removes the
  // noise above the new Nyquist frequency). Equal to tap.r_tap_n when the rates agree.
  if (std::abs(ratio - 1.0) >= 1e-12) {
    double sum_sq = 0.0;
    Eigen::Index count = 0;
    for (std::size_t i = 0; i < in.windows.size(); ++i) {
      const auto seg = in.response_n.segment(in.windows[i].begin, in.pre_end[i]);
      sum_sq += (seg.array() - seg.mean()).square().sum();
      count += seg.size();
    }
    if (count > 1) in.r_tap_n = std::sqrt(sum_sq / static_cast<double>(count));
  }
  return in;
}

}  // namespace chatterlab::app
