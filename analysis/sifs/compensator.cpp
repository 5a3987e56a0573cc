#include "analysis/sifs/compensator.h"

#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <unsupported/Eigen/MatrixFunctions>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/kalman/dare.h"
#include "analysis/signal/harmonic_fit.h"

namespace chatterlab {
namespace sifs {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A number as the stream prints it ("5000", "0.15"), for rules that quote a limit.
std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The time-varying gain is held once |K_k - K_k-1| <= this x |K_k| (compensator.h: the next
// steps change it at rounding level only).
constexpr double kGainConvergence = 1e-13;

// The continuous augmented matrix A_e of 003 eqs 4-50/4-51 as corrected (compensator.h), with
// the plant blocks of the scaled modal realization built here (sensor_model.h documents the
// same blocks; they are three lines, and building them here keeps the model in one place).
MatrixXd augmented_matrix(const std::vector<SensorMode>& modes, double omega_t,
                          Eigen::RowVectorXd* H) {
  const Index k = static_cast<Index>(modes.size());
  const Index n = 2 * k + 3;
  const Index fc = 2 * k, x1f = 2 * k + 1, x2f = 2 * k + 2;
  MatrixXd A = MatrixXd::Zero(n, n);
  H->setZero(n);
  for (Index i = 0; i < k; ++i) {
    const SensorMode& mode = modes[static_cast<std::size_t>(i)];
    const double w = kTwoPi * mode.fn_hz;
    A(2 * i, 2 * i + 1) = w;
    A(2 * i + 1, 2 * i) = -w;
    A(2 * i + 1, 2 * i + 1) = -2.0 * mode.zeta * w;
    A(2 * i + 1, fc) = w;   // B_n f_c
    A(2 * i + 1, x1f) = w;  // B_n C_f x_f, f_ha = x_1f (eq. 4-49)
    (*H)(2 * i) = mode.alpha;
  }
  A(x1f, x2f) = -omega_t * omega_t;  // eq. 4-47
  A(x2f, x1f) = 1.0;
  return A;
}

template <typename Derived>
double inf_norm(const Eigen::MatrixBase<Derived>& X) {
  return X.cwiseAbs().rowwise().sum().maxCoeff();
}

// The gain and data loops for N states (fixed for k <= 6 modes, Eigen::Dynamic above). The
// measurement is a scalar, so the innovation covariance S = H P- H^T + R is a number and
// K = P- H^T / S: one division instead of the generic kalman::measurement_update's LDL^T of an
// M x M matrix and its triangular solves (kalman_filter.h), and the data loop needs no
// covariance at all once the gain sequence is known.
template <int N>
struct Filter {
  using Mat = Eigen::Matrix<double, N, N>;
  using Vec = Eigen::Matrix<double, N, 1>;
  using Row = Eigen::Matrix<double, 1, N>;
  using Gains = Eigen::Matrix<double, N, Eigen::Dynamic>;

  // Time-varying gains K_1.. from P0+ = 0 (003 table 5, eqs 5-48..5-50) with Q = (q/r) Qd_unit
  // and R = 1 (the invariance of compensator.h), at most `limit` of them; returns how many
  // were stored and whether the last one met kGainConvergence.
  static constexpr Index kInitialGainColumns = 4096;
  static Index gain_sequence(const CompensatorModel& m, double q_over_r, Index limit, Gains* gains,
                             bool* converged) {
    const Index n = m.states;
    const Mat F = m.F;
    const Mat Q = q_over_r * m.Qd_unit;
    const Row H = m.H;
    Mat P = Mat::Zero(n, n), FP(n, n), Pm(n, n);
    Vec PHt(n);
    // Grown by doubling: the gain converges within a few thousand steps, so a long record does
    // not hold a gain column per sample (a 10^7-sample record would take GBs).
    gains->resize(n, std::min<Index>(std::max<Index>(limit, 1), kInitialGainColumns));
    *converged = false;
    for (Index k = 0; k < limit; ++k) {
      if (k == gains->cols()) gains->conservativeResize(n, std::min(limit, 2 * gains->cols()));
      FP.noalias() = F * P;
      Pm.noalias() = FP * F.transpose();
      Pm += Q;  // eq. 5-48
      PHt.noalias() = Pm * H.transpose();
      const double S = H.dot(PHt) + 1.0;
      gains->col(k) = PHt / S;                             // eq. 5-49
      P.noalias() = Pm - gains->col(k) * PHt.transpose();  // eq. 5-50, P+ = P- - K H P-
      for (Index j = 1; j < n; ++j) {                      // symmetric to rounding, kept exactly so
        for (Index i = 0; i < j; ++i) P(i, j) = P(j, i) = 0.5 * (P(i, j) + P(j, i));
      }
      if (k > 0 &&
          (gains->col(k) - gains->col(k - 1)).norm() <= kGainConvergence * gains->col(k).norm()) {
        *converged = true;
        return k + 1;
      }
    }
    return limit;
  }

  // x- = F x+ (eq. 5-19), x+ = x- + K_k (z_k - H x-) (eq. 5-18), estimate C_o x+; gain column
  // k while k < steps, then the last column. Nothing is allocated inside the loop.
  static void run(const CompensatorModel& m, const Gains& gains, Index steps,
                  const Eigen::Ref<const VectorXd>& z, VectorXd* estimate) {
    const Index n = m.states;
    const Mat F = m.F;
    const Row H = m.H;
    const Row Co = m.Co;
    Vec x = Vec::Zero(n), xm(n);
    const Index count = z.size();
    const Index varying = std::min(steps - 1, count);
    for (Index i = 0; i < varying; ++i) {
      xm.noalias() = F * x;
      x = xm + gains.col(i) * (z[i] - H.dot(xm));
      (*estimate)[i] = Co.dot(x);
    }
    const Vec K = gains.col(steps - 1);
    for (Index i = std::max<Index>(varying, 0); i < count; ++i) {
      xm.noalias() = F * x;
      x = xm + K * (z[i] - H.dot(xm));
      (*estimate)[i] = Co.dot(x);
    }
  }

  static StepSummary compensate(const CompensatorModel& m, double q_over_r, GainMode gain,
                                const Eigen::Ref<const VectorXd>& z, VectorXd* estimate,
                                Index* gain_steps) {
    StepSummary summary;
    if (gain_steps) *gain_steps = 0;
    estimate->resize(z.size());
    if (z.size() == 0) {
      summary.succeed();
      return summary;
    }
    Gains gains;
    Index steps = 1;
    if (gain == GainMode::kSteadyState) {
      const VectorXd K = steady_gain(m, q_over_r);
      if (K.size() == 0) {
        estimate->setConstant(kNaN);
        summary.fail("compensate: the steady-state gain (DARE) did not converge for q/r = " +
                     number(q_over_r));
        return summary;
      }
      gains = K;
    } else {
      bool converged = false;
      steps = gain_sequence(m, q_over_r, z.size(), &gains, &converged);
      if (gain_steps) *gain_steps = converged ? steps : -1;
      std::ostringstream d;
      if (converged) {
        d << "time-varying gain converged (|K_k - K_k-1| <= " << kGainConvergence
          << " |K_k|) after " << steps << " of " << z.size() << " samples";
        summary.details = d.str();
      } else {
        d << "the time-varying gain had not converged by the end of the record (" << z.size()
          << " samples)";
        summary.warnings.push_back(d.str());
      }
    }
    run(m, gains, steps, z, estimate);
    summary.succeed();
    return summary;
  }
};

// The q sweep's selection rule (format step 4): the smallest n whose RMSE is within
// flat_tolerance of the minimum over the finite values.
void select_optimum(const SweepOptions& options, SweepCurve* curve) {
  double best = std::numeric_limits<double>::infinity();
  for (Index i = 0; i < curve->rmse_n.size(); ++i) {
    if (std::isfinite(curve->rmse_n[i])) best = std::min(best, curve->rmse_n[i]);
  }
  if (!std::isfinite(best)) {
    curve->summary.fail("no q of the sweep gave a finite RMSE");
    return;
  }
  for (Index i = 0; i < curve->rmse_n.size(); ++i) {
    if (curve->rmse_n[i] <= (1.0 + options.flat_tolerance) * best) {
      curve->best_exponent = curve->exponents[static_cast<std::size_t>(i)];
      curve->q_opt = std::ldexp(1.0, curve->best_exponent);
      break;
    }
  }
  curve->summary.succeed();
}

void validate_sweep_options(const SweepOptions& o) {
  require_rule(o.n_first <= o.n_last, "sweep.n_last", o.n_last,
               "must be >= sweep.n_first = " + std::to_string(o.n_first));
  require_rule(o.n_first >= -1000 && o.n_last <= 1000, "sweep exponent range",
               std::to_string(o.n_first) + " .. " + std::to_string(o.n_last),
               "must lie inside -1000 .. 1000");
  require_rule(o.flat_tolerance >= 0.0, "sweep.flat_tolerance", o.flat_tolerance, "must be >= 0");
}

std::string no_harmonic_message(double sf_hz, double lo, double hi, double fs) {
  std::ostringstream m;
  m << "no spindle harmonic h x " << sf_hz << " Hz lies inside band [" << lo << ", " << hi
    << "] Hz and at or below 0.45 x the filter rate " << fs << " Hz";
  return m.str();
}

}  // namespace

const char* to_string(GainMode g) {
  switch (g) {
    case GainMode::kTimeVarying:
      return "time-varying";
    case GainMode::kSteadyState:
      return "steady-state";
  }
  return "?";
}

CompensatorModel make_compensator(const std::vector<SensorMode>& modes, double tpf_hz,
                                  double filter_rate_hz) {
  require_rule(std::isfinite(filter_rate_hz) && filter_rate_hz > 0.0, "filter_rate_hz",
               filter_rate_hz, "must be finite and > 0");
  const double nyquist = 0.5 * filter_rate_hz;
  require_rule(!modes.empty(), "modes", "none", "at least one mode is needed");
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const std::string at = "modes[" + std::to_string(i) + "]";
    require_rule(std::isfinite(modes[i].fn_hz) && modes[i].fn_hz > 0.0 && modes[i].fn_hz < nyquist,
                 at + ".fn_hz", modes[i].fn_hz,
                 "must be > 0 and below the filter Nyquist " + number(nyquist) + " Hz");
    require_rule(std::isfinite(modes[i].zeta) && modes[i].zeta > 0.0, at + ".zeta", modes[i].zeta,
                 "must be finite and > 0");
    require_rule(std::isfinite(modes[i].alpha), at + ".alpha", modes[i].alpha, "must be finite");
  }
  require_rule(std::isfinite(tpf_hz) && tpf_hz > 0.0 && tpf_hz < nyquist, "tpf_hz", tpf_hz,
               "must be > 0 and below the filter Nyquist " + number(nyquist) + " Hz");

  CompensatorModel m;
  m.modes = static_cast<int>(modes.size());
  m.states = 2 * m.modes + 3;
  m.tpf_hz = tpf_hz;
  m.filter_rate_hz = filter_rate_hz;
  const Index n = m.states;
  const Index fc = n - 3, x1f = n - 2, x2f = n - 1;
  const double T = 1.0 / filter_rate_hz;
  const double omega_t = kTwoPi * tpf_hz;  // rad/s (notes/003.md section 4 [FIX])
  const MatrixXd A = augmented_matrix(modes, omega_t, &m.H);
  m.Co = Eigen::RowVectorXd::Zero(n);
  m.Co(fc) = 1.0;  // f_a_hat = f_c + x_1f
  m.Co(x1f) = 1.0;

  // Van Loan (C. F. Van Loan, IEEE TAC 23, 1978): with M = [[-A_e, G Q_c G^T], [0, A_e^T]] T,
  // e^M = [[F^-1, F^-1 Q_d], [0, F^T]]. The resonator block [[0, -w_t^2], [1, 0]] mixes 1 and
  // w_t^2 (~1e7 at 600 Hz) and costs the scaling-and-squaring Pade its relative accuracy in the
  // small entries, so the exponential is taken of D A_e D^-1 with x_2f scaled by w_t (the
  // rotation [[0, -w_t], [w_t, 0]]) and mapped back exactly: F = D^-1 F_s D,
  // Q_d = D^-1 Q_s D^-1 (G = D G: the noise enters f_c and x_1f, unscaled).
  VectorXd d = VectorXd::Ones(n);
  d(x2f) = omega_t;
  const MatrixXd As = d.asDiagonal() * A * d.cwiseInverse().asDiagonal();
  MatrixXd V = MatrixXd::Zero(2 * n, 2 * n);
  V.topLeftCorner(n, n) = -As * T;
  V(fc, n + fc) = T;  // G Q_c G^T T with q = 1
  V(x1f, n + x1f) = T;
  V.bottomRightCorner(n, n) = As.transpose() * T;
  const MatrixXd E = V.exp();
  const MatrixXd Fs = E.bottomRightCorner(n, n).transpose();
  const MatrixXd Qs = Fs * E.topRightCorner(n, n);
  const auto Dinv = d.cwiseInverse().asDiagonal();
  m.F = Dinv * Fs * d.asDiagonal();
  m.Qd_unit = Dinv * (0.5 * (Qs + Qs.transpose())) * Dinv;
  const MatrixXd Finv = Dinv * E.topLeftCorner(n, n) * d.asDiagonal();  // e^{-A_e T}

  m.cond_F = inf_norm(m.F) * inf_norm(Finv);
  m.obsv_rcond = discrete_observability_rcond(A, m.H, T);
  return m;
}

Eigen::VectorXd steady_gain(const CompensatorModel& m, double q_over_r) {
  require_rule(std::isfinite(q_over_r) && q_over_r > 0.0, "steady_gain: q_over_r", q_over_r,
               "must be finite and > 0");
  const kalman::SteadyStateKalman s = kalman::steady_state_gain(
      m.F, m.H, q_over_r * m.Qd_unit, MatrixXd::Identity(1, 1));  // eq. 5-55 corrected
  if (!s.summary.ok()) return VectorXd();
  return s.K.col(0);
}

StepSummary compensate(const CompensatorModel& m, double q, double r, GainMode gain,
                       const Eigen::Ref<const Eigen::VectorXd>& z, Eigen::VectorXd* estimate,
                       Eigen::Index* gain_steps) {
  require_rule(m.states >= 5 && m.F.rows() == m.states, "compensate: model states", m.states,
               "must come from make_compensator (2k + 3 >= 5)");
  require_rule(std::isfinite(q) && q > 0.0, "compensate: q", q, "must be finite and > 0");
  require_rule(std::isfinite(r) && r > 0.0, "compensate: r", r, "must be finite and > 0");
  require_rule(estimate != nullptr, "compensate: estimate", "null", "must point to a vector");
  if (!z.allFinite()) {  // find the sample only on failure: no string per sample
    for (Index i = 0; i < z.size(); ++i) {
      require_rule(std::isfinite(z[i]), "compensate: z[" + std::to_string(i) + "]", z[i],
                   "must be finite");
    }
  }
  const double q_over_r = q / r;
  switch (m.states) {
    case 5:
      return Filter<5>::compensate(m, q_over_r, gain, z, estimate, gain_steps);
    case 7:
      return Filter<7>::compensate(m, q_over_r, gain, z, estimate, gain_steps);
    case 9:
      return Filter<9>::compensate(m, q_over_r, gain, z, estimate, gain_steps);
    case 11:
      return Filter<11>::compensate(m, q_over_r, gain, z, estimate, gain_steps);
    case 13:
      return Filter<13>::compensate(m, q_over_r, gain, z, estimate, gain_steps);
    case 15:
      return Filter<15>::compensate(m, q_over_r, gain, z, estimate, gain_steps);
    default:
      return Filter<Eigen::Dynamic>::compensate(m, q_over_r, gain, z, estimate, gain_steps);
  }
}

std::complex<double> estimator_response(const CompensatorModel& m, const Eigen::VectorXd& K,
                                        double f_hz) {
  require_rule(K.size() == m.states, "estimator_response: K size", K.size(),
               "must equal the model's states " + std::to_string(m.states));
  // x+_k = (I - K H) F x+_k-1 + K z_k, so X = [I - (I - K H) F z^-1]^-1 K Z (format step 7).
  const Index n = m.states;
  const std::complex<double> z_inv = std::polar(1.0, -kTwoPi * f_hz / m.filter_rate_hz);
  const MatrixXd IKHF = (MatrixXd::Identity(n, n) - K * m.H) * m.F;
  const Eigen::MatrixXcd M =
      Eigen::MatrixXcd::Identity(n, n) - z_inv * IKHF.cast<std::complex<double>>();
  const Eigen::VectorXcd y = M.partialPivLu().solve(K.cast<std::complex<double>>());
  return m.Co.cast<std::complex<double>>().dot(y);
}

double usable_bandwidth_hz(const std::vector<SensorMode>& modes, const CompensatorModel& m,
                           const Eigen::VectorXd& K) {
  require_rule(K.size() == 0 || K.size() == m.states, "usable_bandwidth_hz: K size", K.size(),
               "must be 0 (before compensation) or the model's states " + std::to_string(m.states));
  const double nyquist = 0.5 * m.filter_rate_hz;
  // |T_tot| within 10 % of 1 (format step 7).
  for (double f = 1.0; f <= nyquist; f += 1.0) {
    std::complex<double> t = sensor_response(modes, f);
    if (K.size() > 0) t *= estimator_response(m, K, f);
    if (std::abs(std::abs(t) - 1.0) >= 0.1) return f;
  }
  return nyquist;
}

std::vector<int> analysed_harmonics(double sf_hz, double band_lo_hz, double band_hi_hz,
                                    double filter_rate_hz) {
  require_rule(std::isfinite(sf_hz) && sf_hz > 0.0, "sf_hz", sf_hz, "must be finite and > 0");
  require_rule(std::isfinite(filter_rate_hz) && filter_rate_hz > 0.0, "filter_rate_hz",
               filter_rate_hz, "must be finite and > 0");
  require_rule(std::isfinite(band_lo_hz) && std::isfinite(band_hi_hz) && band_lo_hz <= band_hi_hz,
               "band_hz", "[" + number(band_lo_hz) + ", " + number(band_hi_hz) + "]",
               "must be finite with lo <= hi");
  std::vector<int> h;
  const double top = std::min(band_hi_hz, 0.45 * filter_rate_hz);
  for (int i = 1; i * sf_hz <= top; ++i) {
    if (i * sf_hz >= band_lo_hz) h.push_back(i);
  }
  return h;
}

SweepCurve tap_sweep(const TapSweepInput& in, double spindle_rpm, int teeth,
                     const SweepOptions& options) {
  require_rule(in.modes != nullptr, "tap_sweep: modes", "null", "must point to the plant modes");
  require_rule(std::isfinite(spindle_rpm) && spindle_rpm > 0.0, "tap_sweep: spindle_rpm",
               spindle_rpm, "must be finite and > 0");
  require_rule(teeth >= 1, "tap_sweep: teeth", teeth, "must be >= 1");
  require_rule(std::isfinite(in.r_tap_n) && in.r_tap_n > 0.0, "tap_sweep: r_tap_n", in.r_tap_n,
               "must be finite and > 0");
  require_rule(in.hammer_n.size() == in.response_n.size(), "tap_sweep: hammer_n size",
               in.hammer_n.size(),
               "must equal response_n size " + std::to_string(in.response_n.size()));
  require_rule(!in.windows.empty(), "tap_sweep: windows", "none", "at least one hit is needed");
  require_rule(in.pre_end.size() == in.windows.size(), "tap_sweep: pre_end size", in.pre_end.size(),
               "must equal the number of windows " + std::to_string(in.windows.size()));
  validate_sweep_options(options);
  Index longest = 0;
  for (std::size_t w = 0; w < in.windows.size(); ++w) {
    const TapWindow& win = in.windows[w];
    const std::string at = "tap_sweep: windows[" + std::to_string(w) + "]";
    require_rule(win.begin >= 0 && win.begin < win.end && win.end <= in.response_n.size(), at,
                 "[" + std::to_string(win.begin) + ", " + std::to_string(win.end) + ")",
                 "must be non-empty and inside the record of " +
                     std::to_string(in.response_n.size()) + " samples");
    require_rule(in.pre_end[w] >= 1 && in.pre_end[w] <= win.end - win.begin,
                 "tap_sweep: pre_end[" + std::to_string(w) + "]", in.pre_end[w],
                 "must be within 1 .. the window length " + std::to_string(win.end - win.begin));
    longest = std::max(longest, win.end - win.begin);
  }

  SweepCurve curve;
  const double sf = spindle_rpm / kSecondsPerMinute;
  curve.harmonics = analysed_harmonics(sf, in.band_lo_hz, in.band_hi_hz, in.filter_rate_hz);
  if (curve.harmonics.empty()) {
    curve.summary.fail(no_harmonic_message(sf, in.band_lo_hz, in.band_hi_hz, in.filter_rate_hz));
    return curve;
  }
  const CompensatorModel m = make_compensator(*in.modes, teeth * sf, in.filter_rate_hz);

  // e^{-j 2 pi h SF k T} for k from the window start (format step 4), as cosine and sine
  // columns, and their column sums (the pre-impact mean's share of each bin).
  const Index nh = static_cast<Index>(curve.harmonics.size());
  MatrixXd cos_b(longest, nh), sin_b(longest, nh);
  for (Index j = 0; j < nh; ++j) {
    const double dphi =
        kTwoPi * curve.harmonics[static_cast<std::size_t>(j)] * sf / in.filter_rate_hz;
    for (Index k = 0; k < longest; ++k) {
      cos_b(k, j) = std::cos(dphi * static_cast<double>(k));
      sin_b(k, j) = std::sin(dphi * static_cast<double>(k));
    }
  }
  auto amplitudes = [&](const VectorXd& x, std::size_t w) -> Eigen::RowVectorXd {
    const TapWindow& win = in.windows[w];
    const Index L = win.end - win.begin;
    const auto seg = x.segment(win.begin, L);
    const double mean = seg.head(in.pre_end[w]).mean();
    const Eigen::RowVectorXd re =
        seg.transpose() * cos_b.topRows(L) - mean * cos_b.topRows(L).colwise().sum();
    const Eigen::RowVectorXd im =
        seg.transpose() * sin_b.topRows(L) - mean * sin_b.topRows(L).colwise().sum();
    return (2.0 / static_cast<double>(L)) * (re.array().square() + im.array().square()).sqrt();
  };
  std::vector<Eigen::RowVectorXd> hammer(in.windows.size());
  for (std::size_t w = 0; w < in.windows.size(); ++w) hammer[w] = amplitudes(in.hammer_n, w);

  const int count = options.n_last - options.n_first + 1;
  curve.rmse_n.resize(count);
  VectorXd estimate;
  int failed = 0;
  for (int i = 0; i < count; ++i) {
    const int n = options.n_first + i;
    curve.exponents.push_back(n);
    const StepSummary s =
        compensate(m, std::ldexp(1.0, n), in.r_tap_n, in.gain, in.response_n, &estimate);
    if (!s.ok()) {
      curve.rmse_n[i] = kNaN;
      ++failed;
      continue;
    }
    double sum = 0.0;
    for (std::size_t w = 0; w < in.windows.size(); ++w) {
      sum +=
          std::sqrt((amplitudes(estimate, w) - hammer[w]).squaredNorm() / static_cast<double>(nh));
    }
    curve.rmse_n[i] = sum / static_cast<double>(in.windows.size());  // eq. 6-2 sweep
  }
  select_optimum(options, &curve);
  if (failed > 0) {
    curve.summary.warnings.push_back(std::to_string(failed) +
                                     " q values of the sweep gave no estimate (DARE unconverged)");
  }
  return curve;
}

TapMap tap_map(const TapSweepInput& in, const std::vector<double>& rpm, int teeth, int jobs,
               const SweepOptions& options) {
  require_rule(jobs >= 0, "tap_map: jobs", jobs, "must be >= 0 (0: one per hardware thread)");
  validate_sweep_options(options);
  TapMap map;
  map.rpm = rpm;
  for (int n = options.n_first; n <= options.n_last; ++n) map.exponents.push_back(n);
  map.rmse_n = MatrixXd::Constant(static_cast<Index>(rpm.size()),
                                  static_cast<Index>(map.exponents.size()), kNaN);
  map.best_exponent.assign(rpm.size(), -1);

  // One tap_sweep per speed over a shared counter (analysis does not use app/core/parallel.h:
  // the same pattern, std::thread directly). The first exception stops the remaining speeds
  // and is rethrown here.
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads =
      std::clamp(jobs > 0 ? jobs : hw, 1, std::max(1, static_cast<int>(rpm.size())));
  std::atomic<std::size_t> next{0};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < rpm.size(); i = next++) {
      try {
        const SweepCurve c = tap_sweep(in, rpm[i], teeth, options);
        if (!c.summary.ok()) continue;  // no harmonic in the band: a NaN row, best -1
        map.rmse_n.row(static_cast<Index>(i)) = c.rmse_n.transpose();
        map.best_exponent[i] = c.best_exponent;
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        next = rpm.size();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 1; j < threads; ++j) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
  return map;
}

Eigen::VectorXcd cut_harmonics(const Eigen::Ref<const Eigen::VectorXd>& x, double fs_hz,
                               Eigen::Index begin, Eigen::Index end, double sf_hz,
                               const std::vector<int>& harmonics) {
  const signal::HarmonicFit fit = signal::fit_harmonics(x, fs_hz, begin, end, sf_hz, harmonics);
  if (!fit.summary.ok()) throw InputError("cut_harmonics: " + fit.summary.message);
  return fit.c;
}

double spectral_rmse(const Eigen::VectorXcd& c, const Eigen::VectorXcd& c_ref) {
  require_rule(c.size() == c_ref.size() && c.size() > 0, "spectral_rmse: harmonics",
               std::to_string(c.size()) + " vs " + std::to_string(c_ref.size()),
               "must be equal in number and at least one");
  return std::sqrt((c.cwiseAbs() - c_ref.cwiseAbs()).squaredNorm() / static_cast<double>(c.size()));
}

SweepCurve cut_sweep(const CompensatorModel& m, double r, GainMode gain,
                     const Eigen::Ref<const Eigen::VectorXd>& z, Eigen::Index begin,
                     Eigen::Index end, double sf_hz, const std::vector<int>& harmonics,
                     const Eigen::VectorXcd& c_ref, const SweepOptions& options) {
  validate_sweep_options(options);
  require_rule(c_ref.size() == static_cast<Index>(harmonics.size()), "cut_sweep: c_ref size",
               c_ref.size(),
               "must equal the number of harmonics " + std::to_string(harmonics.size()));
  SweepCurve curve;
  curve.harmonics = harmonics;
  if (harmonics.empty()) {
    curve.summary.fail("cut_sweep: no harmonic to analyse");
    return curve;
  }
  const int count = options.n_last - options.n_first + 1;
  curve.rmse_n.resize(count);
  VectorXd estimate;
  int failed = 0;
  for (int i = 0; i < count; ++i) {
    const int n = options.n_first + i;
    curve.exponents.push_back(n);
    const StepSummary s = compensate(m, std::ldexp(1.0, n), r, gain, z, &estimate);
    if (!s.ok()) {
      curve.rmse_n[i] = kNaN;
      ++failed;
      continue;
    }
    curve.rmse_n[i] = spectral_rmse(
        cut_harmonics(estimate, m.filter_rate_hz, begin, end, sf_hz, harmonics), c_ref);
  }
  select_optimum(options, &curve);
  if (failed > 0) {
    curve.summary.warnings.push_back(std::to_string(failed) +
                                     " q values of the sweep gave no estimate (DARE unconverged)");
  }
  return curve;
}

}  // namespace sifs
}  // namespace chatterlab
