#include "app/kinds/tap/tap_step.h"

#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "analysis/frf/frf.h"
#include "analysis/frf/hits.h"
#include "analysis/frf/modal_fit.h"
#include "app/core/input_boundary.h"
#include "app/core/signals.h"
#include "app/formats/frf_text.h"
#include "app/formats/uff58.h"

namespace chatterlab::app {
frf::ResponseKind response_kind_of(const std::string& s) {
  if (s == "velocity") return frf::ResponseKind::kVelocity;
  if (s == "displacement") return frf::ResponseKind::kDisplacement;
  return frf::ResponseKind::kAcceleration;
}

namespace {

frf_text::Ordinate ordinate_of(const std::string& response) {
  if (response == "velocity") return frf_text::Ordinate::kMobility;
  if (response == "displacement") return frf_text::Ordinate::kReceptance;
  return frf_text::Ordinate::kAccelerance;
}

bool is_uff(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e == ".uff" || e == ".unv";
}

// The modal fit of an FRF (from hits or from a file) into `out`.
void fit_into(const frf::Frf& f, const TapSpec& tap, const TapStepOptions& options,
              TapOutcome& out) {
  frf::ModalFitOptions fo = options.fit;
  if (tap.band_hz) fo.band_hz = std::array<double, 2>{tap.band_hz->first, tap.band_hz->second};
  if (tap.modes > 0) fo.n_modes = tap.modes;
  const frf::ModalFit fit = frf::fit_modes(f, fo);
  out.warnings.insert(out.warnings.end(), fit.summary.warnings.begin(), fit.summary.warnings.end());
  out.fit_message = fit.summary.message;
  if (fit.summary.ok()) {
    out.fit_ok = true;
    out.modes = fit.modes;
    out.quality = fit.quality;
    out.fit_nrmse_pct = fit.fit_nrmse_pct;
    out.fitted = fit.fitted;
    out.band_lo_hz = fit.band_lo_hz;
    out.band_hi_hz = fit.band_hi_hz;
  }
}

// An FRF record (function type 4, complex) of a UFF58 file: record `record` (1-based among
// the file's FRF records; 0: the only one), with the coherence record (type 6) of the same
// response and reference when the file has one.
frf_text::FrfTable read_uff_frf(const std::filesystem::path& file, const std::string& label,
                                const std::string& yaml_label, int record) {
  std::vector<uff::Function58> all;
  try {
    all = uff::read_uff58(file);
  } catch (const InputError& e) {
    // The reader names the file by its path: name it as the test does (no machine path).
    std::string m = e.what();
    const std::string path = file.string();
    if (m.rfind(path, 0) == 0) m = label + m.substr(path.size());
    throw InputError(m);
  }
  std::vector<const uff::Function58*> frfs;
  for (const auto& f : all) {
    if (f.function_type == uff::kFrf) frfs.push_back(&f);
  }
  if (frfs.empty()) {
    throw InputError(label + ": no FRF record (dataset 58 function type 4) among its " +
                     std::to_string(all.size()) + " dataset 58 record(s)");
  }
  if (record == 0 && frfs.size() > 1) {
    throw InputError(yaml_label + ": key 'frf.record' absent, but " + label + " holds " +
                     std::to_string(frfs.size()) + " FRF records: say which (1-" +
                     std::to_string(frfs.size()) + ")");
  }
  if (record > static_cast<int>(frfs.size())) {
    throw InputError(yaml_label + ": key 'frf.record' " + std::to_string(record) + ", but " +
                     label + " holds " + std::to_string(frfs.size()) + " FRF record(s)");
  }
  const uff::Function58& f = *frfs[static_cast<std::size_t>(record > 0 ? record - 1 : 0)];
  const std::string which = label + ": FRF record " + std::to_string(record > 0 ? record : 1);
  if (!f.complex_ordinate) throw InputError(which + ": the ordinate is real; an FRF is complex");
  const Eigen::Index n = f.samples();
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    x[i] = f.x.size() == n ? f.x[i] : f.x_start + static_cast<double>(i) * f.dx;
  }
  // The same rules as a text file (increasing, evenly spaced, 0 Hz dropped): written as a
  // table and checked by the one reader would lose the values' precision, so checked here.
  frf_text::FrfTable t;
  const Eigen::Index start = n > 0 && x[0] == 0.0 ? 1 : 0;
  if (start) t.warnings.push_back(which + ": the 0 Hz value is not used");
  const Eigen::Index m = n - start;
  if (m < 3) {
    throw InputError(which + ": " + std::to_string(m) +
                     " frequencies above 0 Hz; an FRF needs at least 3");
  }
  const double df = (x[n - 1] - x[start]) / static_cast<double>(m - 1);
  for (Eigen::Index i = start; i < n; ++i) {
    const double expected = x[start] + static_cast<double>(i - start) * df;
    if (!(x[i] > 0) || std::abs(x[i] - expected) > 0.25 * df) {
      throw InputError(which + ", value " + std::to_string(i + 1) + ": frequency " +
                       std::to_string(x[i]) + " Hz is not on an increasing, even grid");
    }
  }
  t.f_hz = x.tail(m);
  t.h = f.values.tail(m);
  t.df_hz = df;
  t.columns = "UFF58 FRF record " + std::to_string(record > 0 ? record : 1) + " ('" + f.id1 +
              "', " + f.y_unit + (f.z_unit.empty() ? "" : "/" + f.z_unit) + ")";
  for (const auto& c : all) {
    if (c.function_type == uff::kCoherence && !c.complex_ordinate && c.samples() == n &&
        c.response_node == f.response_node && c.response_direction == f.response_direction &&
        c.reference_node == f.reference_node && c.reference_direction == f.reference_direction) {
      t.coherence = c.real.tail(m).cwiseMax(0.0).cwiseMin(1.0);
      t.columns += " and its coherence record";
      break;
    }
  }
  return t;
}

}  // namespace

frf::Frf read_tap_frf(const TestSpec& t, std::vector<std::string>* warnings, std::string* columns,
                      bool* has_coherence) {
  const TapSpec& tap = t.kind_spec<TapSpec>();
  CHATTERLAB_CHECK(tap.frf.has_value(), t.yaml_label + ": the tap test names no frf file");
  const TapFrfInput& in = *tap.frf;
  const std::string label = t.file_label(in.file);
  const std::filesystem::path file = resolve_input_file(t, "frf.file", in.file);
  if (!is_uff(file) && in.record > 0) {
    throw InputError(t.yaml_label + ": key 'frf.record' is only for a UFF58 file (.uff, .unv)");
  }
  frf_text::FrfTable table;
  try {
    if (is_uff(file)) {
      table = read_uff_frf(file, label, t.yaml_label, in.record);
    } else {
      frf_text::ReadOptions ro;
      ro.delimiter = in.delimiter;
      ro.decimal = in.decimal;
      table = frf_text::read_frf_text(file, label, ro);
    }
  } catch (const InputError& e) {
    // The file's own messages name it and the line; say which key named the file.
    const std::string m = e.what();
    if (m.rfind(t.yaml_label, 0) == 0) throw;
    throw InputError(
        m + " [" + t.yaml_label + " key 'frf.file'" +
        (is_uff(file) ? std::string() : "; frf.delimiter, frf.decimal state the dialect") + "]");
  }
  frf::Frf f;
  f.f_hz = table.f_hz;
  f.h1 = frf_text::to_receptance(table.f_hz, table.h, ordinate_of(tap.response));
  f.h2 = f.h1;
  if (table.coherence.size() == table.f_hz.size()) {
    f.coherence = table.coherence;
  } else {
    f.coherence = Eigen::VectorXd::Ones(table.f_hz.size());
  }
  f.df_hz = table.df_hz;
  f.exp_window_tau_s = in.exp_window_tau_s;
  f.hits_used = 0;
  f.summary.succeed();
  if (warnings) warnings->insert(warnings->end(), table.warnings.begin(), table.warnings.end());
  if (columns) *columns = table.columns;
  if (has_coherence) *has_coherence = table.coherence.size() == table.f_hz.size();
  return f;
}

namespace {

// The FRF (from hits or from a file) into the outcome, then the modal fit.
void take_frf(const frf::Frf& f, const TapSpec& tap, const TapStepOptions& options,
              TapOutcome& out) {
  out.f_hz = f.f_hz;
  out.h1 = f.h1;
  out.h2 = f.h2;
  out.coherence = f.coherence;
  out.df_hz = f.df_hz;
  if (f.exp_window_tau_s > 0) out.exp_window_tau_s = f.exp_window_tau_s;
  out.summary.succeed();
  fit_into(f, tap, options, out);
}

}  // namespace

TapOutcome run_tap_test(const TestSpec& t, const TapStepOptions& options) {
  TapOutcome out;
  const TapSpec& tap = t.kind_spec<TapSpec>();
  if (tap.frf) {
    const frf::Frf f = read_tap_frf(t, &out.warnings, &out.frf_columns, &out.has_coherence);
    out.from_file = true;
    out.frf_file = tap.frf->file;
    take_frf(f, tap, options, out);
    return out;
  }
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  const Eigen::VectorXd force = table.channel("force", t.channel("force"));
  const Eigen::VectorXd response = table.channel("response", t.channel("response"));

  frf::HitSet hits;
  if (tap.hits_auto) {
    hits = frf::detect_hits(force, response, t.sample_rate_hz, options.hits);
  } else {
    std::vector<std::array<double, 2>> windows;
    for (const auto& [a, b] : tap.hit_windows_s) windows.push_back({a, b});
    hits = frf::hits_from_windows(force, response, t.sample_rate_hz, windows, options.hits);
  }
  for (const auto& h : hits.hits) {
    out.hits.push_back({h.time_s, h.peak_force_n, h.accepted, h.rejection});
  }
  // hits.summary.warnings only restate the rejections, which out.hits carries.
  if (!hits.summary.ok()) {
    out.summary.fail(label + ": " + hits.summary.message);
    return out;
  }

  const frf::Frf f =
      frf::compute_frf(force, response, hits, response_kind_of(tap.response), options.frf);
  out.warnings.insert(out.warnings.end(), f.summary.warnings.begin(), f.summary.warnings.end());
  if (!f.summary.ok()) {
    out.summary.fail(label + ": " + f.summary.message);
    return out;
  }
  out.hits_used = f.hits_used;
  take_frf(f, tap, options, out);
  return out;
}

}  // namespace chatterlab::app
