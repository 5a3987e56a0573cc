#include "analysis/cutting/dyno_slot.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "analysis/common/angles.h"
#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/signal/pulses.h"

namespace chatterlab {
namespace cutting {

namespace {

// D(psi) of dyno_slot.h from phases sorted ascending and prefix sums of the forces in that
// order (prefix[k] = sum of the first k samples).
class Demodulator {
 public:
  Demodulator(const std::vector<double>& phi_rad, const Eigen::Ref<const Eigen::Matrix2Xd>& F) {
    const std::size_t n = phi_rad.size();
    std::vector<double> wrapped(n);
    std::transform(phi_rad.begin(), phi_rad.end(), wrapped.begin(), wrap_2pi);
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return wrapped[a] < wrapped[b]; });
    phase_.resize(n);
    prefix_.resize(n + 1);
    prefix_[0].setZero();
    for (std::size_t k = 0; k < n; ++k) {
      phase_[k] = wrapped[order[k]];
      prefix_[k + 1] = prefix_[k] + F.col(static_cast<Eigen::Index>(order[k]));
    }
  }

  Eigen::Vector2d D(double psi) const {
    const double a = wrap_2pi(psi);
    const double b = a + kPi;
    Eigen::Vector2d half;  // sum over phases in [a, a + pi), wrapping at 2 pi
    if (b <= kTwoPi) {
      half = prefix_[index(b)] - prefix_[index(a)];
    } else {
      half = prefix_.back() - prefix_[index(a)] + prefix_[index(b - kTwoPi)];
    }
    return (2.0 * half - prefix_.back()) / static_cast<double>(phase_.size());
  }

 private:
  std::size_t index(double phase) const {
    return static_cast<std::size_t>(std::lower_bound(phase_.begin(), phase_.end(), phase) -
                                    phase_.begin());
  }
  std::vector<double> phase_;
  std::vector<Eigen::Vector2d> prefix_;
};

// First NaN of a channel: returns false and fills `why` if one is found.
bool check_finite(const Eigen::Ref<const Eigen::VectorXd>& x, const char* name, std::string* why) {
  Eigen::Index count = 0;
  Eigen::Index first = -1;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (std::isnan(x[i])) {
      if (first < 0) first = i;
      ++count;
    }
  }
  if (count == 0) return true;
  std::ostringstream m;
  m << "NaN samples in " << name << ": " << count << " of " << x.size() << ", first at index "
    << first;
  *why = m.str();
  return false;
}

double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double sample_std(const std::vector<double>& v) {
  if (v.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const double m = mean(v);
  double ss = 0.0;
  for (double x : v) ss += (x - m) * (x - m);
  return std::sqrt(ss / static_cast<double>(v.size() - 1));
}

}  // namespace

double switching_phase_rad(const std::vector<double>& phi_rad,
                           const Eigen::Ref<const Eigen::Matrix2Xd>& F, double coarse_step_rad,
                           double resolution_rad, double* contrast) {
  if (phi_rad.empty() || static_cast<Eigen::Index>(phi_rad.size()) != F.cols()) {
    std::ostringstream m;
    m << "switching_phase_rad: " << phi_rad.size() << " phases and " << F.cols()
      << " force columns: must be equal and > 0";
    throw InputError(m.str());
  }
  if (!(coarse_step_rad > 0.0) || !(resolution_rad > 0.0) || resolution_rad > coarse_step_rad) {
    std::ostringstream m;
    m << "switching_phase_rad: coarse_step_rad = " << coarse_step_rad
      << ", resolution_rad = " << resolution_rad << ": must satisfy 0 < resolution <= coarse";
    throw InputError(m.str());
  }
  const Demodulator demod(phi_rad, F);

  // Coarse grid over [0, pi): D(psi + pi) = -D(psi), so half a turn holds every magnitude.
  const int n_coarse = static_cast<int>(std::ceil(kPi / coarse_step_rad));
  double best_psi = 0.0;
  double best = -1.0;
  for (int j = 0; j < n_coarse; ++j) {
    const double psi = j * coarse_step_rad;
    const double mag = demod.D(psi).norm();
    if (mag > best) {
      best = mag;
      best_psi = psi;
    }
  }

  // Fine grid over +-1 coarse step. |D| is piecewise constant in psi (it changes only when
  // psi or psi + pi passes a sample phase), so take the centre of the run of equal maxima.
  const int n_fine = static_cast<int>(std::ceil(2.0 * coarse_step_rad / resolution_rad));
  const double start = best_psi - coarse_step_rad;
  std::vector<double> mags(static_cast<std::size_t>(n_fine) + 1);
  for (int k = 0; k <= n_fine; ++k)
    mags[static_cast<std::size_t>(k)] = demod.D(start + k * resolution_rad).norm();
  const auto it_max = std::max_element(mags.begin(), mags.end());
  std::size_t first = static_cast<std::size_t>(it_max - mags.begin());
  std::size_t last = first;
  while (last + 1 < mags.size() && mags[last + 1] == *it_max) ++last;
  const double psi = start + 0.5 * static_cast<double>(first + last) * resolution_rad;

  const double psi_wrapped = std::fmod(wrap_2pi(psi), kPi);
  if (contrast != nullptr) {
    const double mean_norm = F.colwise().norm().mean();
    *contrast = mean_norm > 0.0 ? demod.D(psi_wrapped).norm() / mean_norm : 0.0;
  }
  return psi_wrapped;
}

SlotRecordResult analyse_slot_record(const Eigen::Ref<const Eigen::VectorXd>& Fx_N,
                                     const Eigen::Ref<const Eigen::VectorXd>& Fy_N,
                                     const Eigen::Ref<const Eigen::VectorXd>& zero_V, double fs_hz,
                                     double spindle_rpm, const DynoOptions& options) {
  validate(options);
  if (!(fs_hz > 0.0) || !std::isfinite(fs_hz)) {
    throw InputError("analyse_slot_record: fs_hz = " + stream_text(fs_hz) + ": must be > 0");
  }
  if (!(spindle_rpm > 0.0) || !std::isfinite(spindle_rpm)) {
    throw InputError("analyse_slot_record: spindle_rpm = " + stream_text(spindle_rpm) +
                     ": must be > 0");
  }
  if (Fx_N.size() != Fy_N.size() || Fx_N.size() != zero_V.size()) {
    std::ostringstream m;
    m << "analyse_slot_record: Fx_N has " << Fx_N.size() << " samples, Fy_N " << Fy_N.size()
      << ", zero_V " << zero_V.size() << ": must be equal";
    throw InputError(m.str());
  }

  SlotRecordResult r;
  std::string why;
  if (!check_finite(Fx_N, "Fx_N", &why) || !check_finite(Fy_N, "Fy_N", &why) ||
      !check_finite(zero_V, "zero_V", &why)) {
    r.summary.fail(why);
    return r;
  }

  const double expected = fs_hz * 60.0 / spindle_rpm;  // samples per revolution
  if (expected < options.min_samples_per_revolution) {
    r.summary.fail("too few samples per revolution: fs_hz * 60 / spindle_rpm = " +
                   stream_text(expected) + " < " + stream_text(options.min_samples_per_revolution));
    return r;
  }

  // Whole revolutions between zero-count rising edges.
  const std::vector<double> edges =
      signal::rising_edges(zero_V, options.zero_threshold_V, options.zero_hysteresis_V);
  if (edges.empty()) {
    r.summary.fail("no zero-count edges: zero_V never rises through " +
                   stream_text(options.zero_threshold_V) + " V after being below " +
                   stream_text(options.zero_threshold_V - options.zero_hysteresis_V) + " V (max " +
                   stream_text(zero_V.size() > 0 ? zero_V.maxCoeff() : 0.0) + " V)");
    return r;
  }
  const int revs = static_cast<int>(edges.size()) - 1;
  if (revs < options.min_revolutions) {
    r.summary.fail("fewer than " + std::to_string(options.min_revolutions) +
                   " whole revolutions: " + std::to_string(revs) + " between " +
                   std::to_string(edges.size()) + " zero-count edges");
    return r;
  }
  for (int k = 0; k < revs; ++k) {
    const double d = edges[static_cast<std::size_t>(k) + 1] - edges[static_cast<std::size_t>(k)];
    if (std::abs(d / expected - 1.0) > options.rpm_tolerance) {
      r.summary.fail(
          "zero-count edge spacing disagrees with spindle_rpm = " + stream_text(spindle_rpm) +
          " by more than " + stream_text(100.0 * options.rpm_tolerance) + " %: interval " +
          std::to_string(k) + " (from sample " +
          stream_text(edges[static_cast<std::size_t>(k)], 9) + ") is " + stream_text(d) +
          " samples (" + stream_text(fs_hz * 60.0 / d) + " rpm), expected " +
          stream_text(expected) + " samples");
      return r;
    }
  }
  r.revolutions = revs;
  r.measured_rpm = fs_hz * 60.0 * revs / (edges.back() - edges.front());

  // Samples of the whole revolutions: indices in [edges.front(), edges.back()).
  const Eigen::Index i0 = static_cast<Eigen::Index>(std::ceil(edges.front()));
  const Eigen::Index i1 = static_cast<Eigen::Index>(std::ceil(edges.back()));
  const Eigen::Index n = i1 - i0;

  // 000 sec. 3.2: the rotating axes average zero over whole revolutions, so the mean is the
  // channel offset.
  r.offset_x_N = Fx_N.segment(i0, n).mean();
  r.offset_y_N = Fy_N.segment(i0, n).mean();

  // Revolution phase of every sample (fraction of its zero-count interval), and the
  // revolution it belongs to.
  std::vector<double> phi(static_cast<std::size_t>(n));
  std::vector<int> rev_of(static_cast<std::size_t>(n));
  Eigen::Matrix2Xd F(2, n);
  int k = 0;
  for (Eigen::Index i = i0; i < i1; ++i) {
    const double x = static_cast<double>(i);
    while (x >= edges[static_cast<std::size_t>(k) + 1]) ++k;
    const double e0 = edges[static_cast<std::size_t>(k)];
    const double e1 = edges[static_cast<std::size_t>(k) + 1];
    const std::size_t j = static_cast<std::size_t>(i - i0);
    phi[j] = kTwoPi * (x - e0) / (e1 - e0);
    rev_of[j] = k;
    F(0, i - i0) = Fx_N[i] - r.offset_x_N;
    F(1, i - i0) = Fy_N[i] - r.offset_y_N;
  }
  double contrast = 0.0;
  const double psi = switching_phase_rad(phi, F, options.theta_coarse_step_deg * kDegToRad,
                                         options.theta_resolution_deg * kDegToRad, &contrast);
  r.theta_dyn_rad = psi > 0.5 * kPi ? psi - kPi : psi;  // nearest tooth change: (-pi/2, pi/2]
  r.switching_contrast = contrast;

  // 000 eqs 3.1-3.2, averaged over each whole revolution.
  const double c = std::cos(r.theta_dyn_rad);
  const double s = std::sin(r.theta_dyn_rad);
  std::vector<double> sum_t(static_cast<std::size_t>(revs), 0.0);
  std::vector<double> sum_r(static_cast<std::size_t>(revs), 0.0);
  std::vector<int> count(static_cast<std::size_t>(revs), 0);
  double all_t = 0.0;
  double all_r = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double ft = std::abs(F(0, j) * c + F(1, j) * s);
    const double fr = std::abs(-F(0, j) * s + F(1, j) * c);
    const std::size_t q = static_cast<std::size_t>(rev_of[static_cast<std::size_t>(j)]);
    sum_t[q] += ft;
    sum_r[q] += fr;
    ++count[q];
    all_t += ft;
    all_r += fr;
  }
  for (std::size_t q = 0; q < sum_t.size(); ++q) {
    r.per_revolution_Ft_N.push_back(sum_t[q] / count[q]);
    r.per_revolution_Fr_N.push_back(sum_r[q] / count[q]);
  }
  r.mean_Ft_N = all_t / static_cast<double>(n);
  r.mean_Fr_N = all_r / static_cast<double>(n);
  r.spread_Ft_N = sample_std(r.per_revolution_Ft_N);
  r.spread_Fr_N = sample_std(r.per_revolution_Fr_N);

  if (contrast < options.switching_contrast_warning) {
    r.summary.warnings.push_back(
        "weak tooth-change signature: |D(theta_dyn)| / mean|F| = " + stream_text(contrast, 3) +
        " < " + stream_text(options.switching_contrast_warning, 3) +
        " (not a clean two-tooth slot: air cut, runout or chatter?); theta_dyn is unreliable");
  }
  r.summary.succeed();
  return r;
}

}  // namespace cutting
}  // namespace chatterlab
