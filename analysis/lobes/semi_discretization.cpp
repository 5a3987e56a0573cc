// Method 1 of lobes.h: first-order semi-discretization, Insperger & Stepan, "Updated
// semi-discretization method for periodic delay-differential equations with discrete delay",
// Int. J. Numer. Meth. Engng 61 (2004) 117-141 ("IS2004"), and their book "Semi-Discretization
// for Time-Delay Systems" (Springer 2011, ch. 3).
//
// First-order form of lobes.h's model, z = [q; q'] (q: all x modes, then all y modes, d of them):
//   z'(t) = (A + b B(t)) z(t) - b B(t) z(t - tau),   A = [0 I; -M^-1 K  -M^-1 C],
//   B(t) = [0 0; W(t) 0],   W(t) = M^-1 P^T H(t) P   (P: 2 x d, x = sum of x modes' q, ...).
// On interval [t_i, t_i + dt], dt = tau / m, B is replaced by its mean B_i (exact mean of H over
// the interval's angles, directional.h) and the delayed state by the linear interpolation
// of q_{i-m+1}, q_{i-m} (IS2004 eq. 11, first order). The exact solution of that ODE
// (IS2004 eqs 13-16) gives
//   z_{i+1} = Phi_i z_i + G1_i Bd_i q_{i-m+1} + (G0_i - G1_i) Bd_i q_{i-m},   Bd_i = -b W_i,
//   Phi_i = exp(A_i dt), G0_i = int_0^dt exp(A_i s) ds, G1_i = int_0^dt exp(A_i s)(dt - s)/dt ds
// (A_i = A + b B_i), all three from one exponential of the Van Loan block matrix
//   exp([A_i dt  I  0; 0 0 I; 0 0 0]) = [Phi_i  G0_i/dt  G1_i/dt; ...].
// The discrete map on Y_i = [z_i; q_{i-1}; ...; q_{i-m}] (IS2004 eq. 18, the delayed part a
// shift) is applied to the monodromy matrix row block by row block (no dense products), and
// the Floquet transition matrix over the principal period T (IS2004 eq. 20) is tested by its
// eigenvalues: stable iff all |mu| < 1. Delayed blocks that no engaged interval reads leave
// zero columns; the eigenvalues are taken of the submatrix without them (set_speed).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>
#include <optional>
#include <thread>
#include <unsupported/Eigen/MatrixFunctions>
#include <utility>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/lobes/directional.h"
#include "analysis/lobes/lobes.h"
#include "analysis/milling/engagement.h"

namespace chatterlab {
namespace lobes {
namespace {

void validate_options(const SemiDiscretizationOptions& o) {
  require_rule(o.steps_per_tooth >= 2, "semi_discretization.steps_per_tooth", o.steps_per_tooth,
               "must be >= 2");
  require_rule(o.coarse_depths >= 1, "semi_discretization.coarse_depths", o.coarse_depths,
               "must be >= 1");
  require_rule(std::isfinite(o.depth_rel_tol) && o.depth_rel_tol > 0.0 && o.depth_rel_tol < 1.0,
               "semi_discretization.depth_rel_tol", o.depth_rel_tol, "must be > 0 and < 1");
  require_rule(o.threads >= 1, "semi_discretization.threads", o.threads, "must be >= 1");
}

// The delay state's size (steps_per_tooth x modes) bounds the eigenvalue problem (at most
// 2 d + m d square): kMaxDelayStates keeps it under 8,192^2 doubles (512 MB) per thread.
void validate_size(const LobesInput& in, const SemiDiscretizationOptions& o) {
  const auto d = static_cast<long long>(in.x_modes.size() + in.y_modes.size());
  require_rule(static_cast<long long>(o.steps_per_tooth) * d + 2 * d <= kMaxDelayStates,
               "semi_discretization.steps_per_tooth x modes", o.steps_per_tooth * d,
               "must be at most " + std::to_string(kMaxDelayStates) +
                   " (the delay state of the eigenvalue problem)");
}

bool equal_teeth(const LobesInput& in) {
  for (int p = 1; p < in.teeth; ++p) {
    if (in.Kt_N_m2[p] != in.Kt_N_m2[0] || in.Kr_N_m2[p] != in.Kr_N_m2[0]) return false;
  }
  return true;
}

struct Mode {
  int axis;  // 0: x, 1: y
  ModalParameters p;
};

std::vector<Mode> all_modes(const LobesInput& in) {
  std::vector<Mode> modes;
  for (const ModalParameters& p : in.x_modes) modes.push_back({0, p});
  for (const ModalParameters& p : in.y_modes) modes.push_back({1, p});
  return modes;
}

// Natural frequency of the mode with the highest receptance peak, about 1 / (c omega_n)
// (= 1 / (2 k zeta)): the reference of the chatter-frequency rule (docs/lobes.md).
double dominant_frequency_hz(const std::vector<Mode>& modes) {
  double best = -1.0, fn = 0.0;
  for (const Mode& m : modes) {
    const double wn = std::sqrt(m.p.k_N_m / m.p.m_kg);
    const double peak =
        m.p.c_kg_s > 0.0 ? 1.0 / (m.p.c_kg_s * wn) : std::numeric_limits<double>::infinity();
    if (peak > best) {
      best = peak;
      fn = wn / kTwoPi;
    }
  }
  return fn;
}

// Depth-independent part of one speed's discrete map.
struct SpeedModel {
  double dt_s = 0.0;
  double period_s = 0.0;
  int intervals = 0;               // K = m (tooth period) or N m (revolution)
  std::vector<Eigen::MatrixXd> W;  // per interval, d x d (empty when not engaged)
};

// State size S = 2 d fixed at compile time for d <= 4 modes in all (one mode per axis: 4; two
// per axis: 8), else Dynamic (Eigen's matrix exponential then allocates per interval).
template <int S>
class Kernel {
 public:
  using MatS = Eigen::Matrix<double, S, S>;
  static constexpr int S3 = S == Eigen::Dynamic ? Eigen::Dynamic : 3 * S;
  using MatE = Eigen::Matrix<double, S3, S3>;
  using MatSd = Eigen::Matrix<double, S, Eigen::Dynamic>;

  Kernel(const LobesInput& in, const SemiDiscretizationOptions& o)
      : in_(in), o_(o), modes_(all_modes(in)) {
    d_ = static_cast<int>(modes_.size());
    s_ = 2 * d_;
    m_ = o.steps_per_tooth;
    // Scaled state z = [q; qdot / omega_n] (per mode): the same multipliers (a similarity), and
    // entries of A dt of the order of omega_n dt instead of omega_n^2 dt, so that the matrix
    // exponentials need no scaling and squaring (docs/lobes.md "Speed").
    A_ = MatS::Zero(s_, s_);
    for (int a = 0; a < d_; ++a) {
      const ModalParameters& p = modes_[static_cast<std::size_t>(a)].p;
      const double wn = std::sqrt(p.k_N_m / p.m_kg);
      A_(a, d_ + a) = wn;
      A_(d_ + a, a) = -wn;
      A_(d_ + a, d_ + a) = -p.c_kg_s / p.m_kg;
    }
    E_ = MatE::Zero(3 * s_, 3 * s_);
    E_.block(0, s_, s_, s_).setIdentity();
    E_.block(s_, 2 * s_, s_, s_).setIdentity();
    R1_.resize(s_, d_);
    R0_.resize(s_, d_);
    window_ = milling::engagement_window(in.operation, in.radius_m, in.radial_immersion_m);
    revolution_ = o.force_revolution_period || !equal_teeth(in);
    fdom_hz_ = dominant_frequency_hz(modes_);
  }

  void set_speed(double rpm) {
    const int n = in_.teeth;
    const double tau = 60.0 / (n * rpm);
    model_.dt_s = tau / m_;
    model_.intervals = revolution_ ? n * m_ : m_;
    model_.period_s = model_.dt_s * model_.intervals;
    const double dtheta = kTwoPi / (n * m_);
    model_.W.assign(static_cast<std::size_t>(model_.intervals), Eigen::MatrixXd());
    for (int i = 0; i < model_.intervals; ++i) {
      Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
      for (int p = 0; p < n; ++p) {
        H += engaged_integral(in_.Kt_N_m2[p], in_.Kr_N_m2[p], i * dtheta + p * kTwoPi / n, dtheta,
                              window_.entry_rad, window_.exit_rad);
      }
      if (H.isZero(0.0)) continue;
      H /= dtheta;  // mean of H(t) over the interval
      Eigen::MatrixXd W(d_, d_);
      for (int a = 0; a < d_; ++a) {
        for (int c = 0; c < d_; ++c) {
          const ModalParameters& pa = modes_[static_cast<std::size_t>(a)].p;
          W(a, c) = H(modes_[a].axis, modes_[c].axis) / (pa.m_kg * std::sqrt(pa.k_N_m / pa.m_kg));
        }
      }
      model_.W[static_cast<std::size_t>(i)] = W;
    }
    phi_free_ = (A_ * model_.dt_s).exp();
    // Columns of the monodromy matrix that can be non-zero: z_0, and the initial delayed block
    // q_{-j} (1 <= j <= m) only if a step reads it, i.e. step m - 1 - j (as q_{i-m+1}) or step
    // m - j (as q_{i-m}) is engaged; every other block is shifted out unread, its column stays 0.
    // For X = X[:, C] E_C^T the non-zero eigenvalues are those of the principal submatrix
    // X[C, C]: at low immersion a far smaller eigenvalue problem (same multipliers).
    std::vector<bool> used(static_cast<std::size_t>(m_ + 1), false);
    for (int i = 0; i < model_.intervals; ++i) {
      if (model_.W[static_cast<std::size_t>(i)].size() == 0) continue;
      for (const int j : {m_ - 1 - i, m_ - i}) {
        if (j >= 1 && j <= m_) used[static_cast<std::size_t>(j)] = true;
      }
    }
    cols_.clear();
    for (int r = 0; r < s_; ++r) cols_.push_back(r);
    for (int j = 1; j <= m_; ++j) {
      if (!used[static_cast<std::size_t>(j)]) continue;
      for (int r = 0; r < d_; ++r) cols_.push_back(s_ + (j - 1) * d_ + r);
    }
    const auto c = static_cast<Eigen::Index>(cols_.size());
    // Position in C of each initial delayed block's first column (-1: not in C, never read).
    block_pos_.assign(static_cast<std::size_t>(m_ + 1), -1);
    for (Eigen::Index a = s_; a < c; a += d_) {
      block_pos_[static_cast<std::size_t>((cols_[a] - s_) / d_ + 1)] = static_cast<int>(a);
    }
    if (Xc_.rows() != c) {
      Xc_.resize(c, c);
      // Constructed in place: assigning a fresh solver copies its members before any compute()
      // set them (an uninitialized ComputationInfo: undefined behaviour under UBSan).
      es_.emplace(c);
    }
    top_.resize(s_, c);
    next_.resize(s_, c);
    hist_.resize(static_cast<Eigen::Index>(m_ + 1) * d_, c);
  }

  // Critical (largest-modulus) Floquet multiplier at depth b.
  //
  // Only the columns C of the monodromy matrix are propagated (the others end zero, set_speed),
  // and the delayed part of Y_i is never moved: q_k (k >= 0) is kept as block k mod (m + 1) of
  // hist_, a ring of the last m + 1 (the
  // first d rows of z_k), and q_{-j} is block j of the initial identity. The map of interval i
  // reads q_{i-m+1} and q_{i-m} from there, so a step costs O(S^2 |C|) instead of the O(D^2) of
  // shifting the whole delay state (docs/lobes.md "Speed").
  std::complex<double> critical_multiplier(double b) {
    const double dt = model_.dt_s;
    const Eigen::Index c = Xc_.rows();
    top_.setZero();
    for (int r = 0; r < s_; ++r) top_(r, r) = 1.0;  // C begins with the s columns of z_0
    hist_.topRows(d_) = top_.topRows(d_);
    // next_ += R q_k for the k of q_{i-m+1} or q_{i-m}.
    const auto add_delayed = [&](const MatSd& R, int k) {
      if (k >= 0) {
        next_.noalias() += R * hist_.middleRows(slot(k), d_);
        return;
      }
      const int pos = block_pos_[static_cast<std::size_t>(-k)];
      if (pos < 0) return;  // cannot happen: an engaged step's blocks are in C
      for (int r = 0; r < d_; ++r) next_.col(pos + r) += R.col(r);
    };
    for (int i = 0; i < model_.intervals; ++i) {
      const Eigen::MatrixXd& W = model_.W[static_cast<std::size_t>(i)];
      if (W.size() == 0) {
        next_.noalias() = phi_free_ * top_;
      } else {
        E_.block(0, 0, s_, s_) = A_ * dt;
        E_.block(d_, 0, d_, d_) += (b * dt) * W;
        Ex_ = E_.exp();
        R1_.noalias() = (-b * dt) * Ex_.block(0, 2 * s_ + d_, s_, d_) * W;
        R0_.noalias() =
            (-b * dt) * (Ex_.block(0, s_ + d_, s_, d_) - Ex_.block(0, 2 * s_ + d_, s_, d_)) * W;
        next_.noalias() = Ex_.block(0, 0, s_, s_) * top_;
        add_delayed(R1_, i - m_ + 1);
        add_delayed(R0_, i - m_);
      }
      top_.swap(next_);
      // Block i + 1 takes the slot of q_{i-m}, read above for the last time.
      hist_.middleRows(slot(i + 1), d_) = top_.topRows(d_);
    }
    // Rows C of Y_K = [z_K; q_{K-1}; ...; q_{K-m}] (K >= m: every q from hist_).
    const int K = model_.intervals;
    for (Eigen::Index a = 0; a < c; ++a) {
      const int row = cols_[static_cast<std::size_t>(a)];
      if (row < s_) {
        Xc_.row(a) = top_.row(row);
      } else {
        const int j = (row - s_) / d_ + 1, r = (row - s_) % d_;
        Xc_.row(a) = hist_.row(slot(K - j) + r);
      }
    }
    es_->compute(Xc_, false);
    const auto& ev = es_->eigenvalues();
    Eigen::Index k = 0;
    ev.cwiseAbs().maxCoeff(&k);
    return ev(k);
  }

  // First row of q_k in the ring hist_ (k >= 0).
  Eigen::Index slot(int k) const { return static_cast<Eigen::Index>(k % (m_ + 1)) * d_; }

  // log |mu| at depth 0: the free motion over the period, T times the largest real part of
  // the modes' eigenvalues (-zeta wn, or -zeta wn + wn sqrt(zeta^2 - 1) when overdamped).
  double free_log_multiplier() const {
    double largest = -std::numeric_limits<double>::infinity();
    for (const Mode& m : modes_) {
      const double wn = std::sqrt(m.p.k_N_m / m.p.m_kg);
      const double zeta = m.p.c_kg_s / (2.0 * m.p.m_kg * wn);
      largest =
          std::max(largest, zeta < 1.0 ? -zeta * wn : wn * (std::sqrt(zeta * zeta - 1) - zeta));
    }
    return largest * model_.period_s;
  }

  // docs/lobes.md: f = |arg(mu) / (2 pi) + k| / T with the integer k that brings f nearest the
  // natural frequency of the dominant mode.
  double chatter_hz(std::complex<double> mu) const {
    const double T = model_.period_s;
    const double a = std::arg(mu) / kTwoPi;
    const double k0 = std::round(fdom_hz_ * T - a);
    double best = std::numeric_limits<double>::infinity(), f_best = 0.0;
    for (double k = k0 - 1.0; k <= k0 + 1.0; k += 1.0) {
      const double f = std::abs(a + k) / T;
      if (std::abs(f - fdom_hz_) < best) {
        best = std::abs(f - fdom_hz_);
        f_best = f;
      }
    }
    return f_best;
  }

  SpeedResult solve(double rpm) {
    set_speed(rpm);
    SpeedResult r;
    r.spindle_rpm = rpm;
    const double bmax = in_.max_depth_m;
    double lo = 0.0, hi = -1.0;
    std::complex<double> mu_hi;
    for (int j = 1; j <= o_.coarse_depths; ++j) {
      const double b = bmax * j / o_.coarse_depths;
      const std::complex<double> mu = critical_multiplier(b);
      if (!(std::abs(mu) < 1.0)) {  // a non-finite multiplier counts as unstable
        hi = b;
        mu_hi = mu;
        break;
      }
      lo = b;
      r.critical_multiplier_abs = std::abs(mu);
    }
    if (hi < 0.0) return r;  // stable up to max depth
    // Between the last stable and the first unstable depth: the Illinois variant of regula
    // falsi on f(b) = log |mu(b)| (f(lo) < 0 <= f(hi)), with a bisection step whenever a step
    // did not halve the bracket, so never slower than half the speed of bisection. At b = 0
    // |mu| is the free motion's exp(-min(c / 2m) T), exact in this discretization.
    double flo = lo > 0.0 ? std::log(r.critical_multiplier_abs) : free_log_multiplier();
    double fhi = std::log(std::abs(mu_hi));
    int side = 0;
    bool bisect = !(flo < 0.0);
    while (hi - lo > o_.depth_rel_tol * hi) {
      const double width = hi - lo;
      double b = 0.5 * (lo + hi);
      if (!bisect && std::isfinite(flo) && std::isfinite(fhi) && fhi > flo) {
        const double eps = 0.25 * o_.depth_rel_tol * hi;  // keep clear of the ends
        b = std::clamp((lo * fhi - hi * flo) / (fhi - flo), lo + eps, hi - eps);
      }
      if (!std::isfinite(b)) b = 0.5 * (lo + hi);
      const std::complex<double> mu = critical_multiplier(b);
      const double f = std::log(std::abs(mu));
      if (!(f < 0.0)) {  // unstable, or a non-finite multiplier
        hi = b;
        fhi = f;
        mu_hi = mu;
        if (side == 1) flo *= 0.5;
        side = 1;
      } else {
        lo = b;
        flo = f;
        if (side == -1) fhi *= 0.5;
        side = -1;
      }
      bisect = !(hi - lo <= 0.5 * width) || !(flo < 0.0);
    }
    r.limit_depth_m = hi;
    r.critical_multiplier_abs = std::abs(mu_hi);
    r.critical_multiplier = mu_hi;
    if (std::abs(mu_hi.imag()) > 1e-9 * std::abs(mu_hi)) {
      r.type = BoundaryType::kHopf;
    } else {
      r.type = mu_hi.real() < 0.0 ? BoundaryType::kFlip : BoundaryType::kFold;
    }
    r.chatter_hz = chatter_hz(mu_hi);
    return r;
  }

 private:
  const LobesInput& in_;
  SemiDiscretizationOptions o_;
  std::vector<Mode> modes_;
  int d_ = 0, s_ = 0, m_ = 0;
  MatS A_, phi_free_;
  MatE E_, Ex_;
  MatSd top_, next_;      // z_i and z_{i+1}, columns C
  Eigen::MatrixXd hist_;  // ring of m + 1 blocks of d rows: q_k = first d rows of z_k, columns C
  std::vector<int> block_pos_;
  Eigen::MatrixXd Xc_;     // X[C, C]
  std::vector<int> cols_;  // C: the columns of X that can be non-zero (set_speed)
  MatSd R1_, R0_;
  std::optional<Eigen::EigenSolver<Eigen::MatrixXd>> es_;
  milling::EngagementWindow window_;
  bool revolution_ = false;
  double fdom_hz_ = 0.0;
  SpeedModel model_;
};

// Runs fn(kernel, i) for every speed i, speeds split over o.threads threads, one kernel each.
template <int S, class Fn>
void for_speeds(const LobesInput& in, const SemiDiscretizationOptions& o, Fn&& fn) {
  const std::size_t n = in.spindle_rpm.size();
  const auto threads = std::min<std::size_t>(static_cast<std::size_t>(o.threads), n);
  auto work = [&](std::size_t t) {
    Kernel<S> k(in, o);
    for (std::size_t i = t; i < n; i += threads) fn(k, i);
  };
  if (threads <= 1) {
    work(0);
    return;
  }
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(work, t);
  for (std::thread& th : pool) th.join();
}

template <int S>
void solve_all(const LobesInput& in, const SemiDiscretizationOptions& o,
               std::vector<SpeedResult>& out) {
  for_speeds<S>(in, o, [&](Kernel<S>& k, std::size_t i) { out[i] = k.solve(in.spindle_rpm[i]); });
}

template <int S>
void grid_all(const LobesInput& in, const SemiDiscretizationOptions& o,
              const std::vector<double>& depths_m, Eigen::MatrixXd& out) {
  for_speeds<S>(in, o, [&](Kernel<S>& k, std::size_t i) {
    k.set_speed(in.spindle_rpm[i]);
    for (std::size_t j = 0; j < depths_m.size(); ++j) {
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
          std::abs(k.critical_multiplier(depths_m[j]));
    }
  });
}

// Dispatch on the number of modes: fixed sizes up to 4 modes in all.
template <template <int> class Job, class... Args>
void by_size(std::size_t modes, Args&&... args) {
  switch (modes) {
    case 1:
      Job<2>::run(std::forward<Args>(args)...);
      return;
    case 2:
      Job<4>::run(std::forward<Args>(args)...);
      return;
    case 3:
      Job<6>::run(std::forward<Args>(args)...);
      return;
    case 4:
      Job<8>::run(std::forward<Args>(args)...);
      return;
    default:
      Job<Eigen::Dynamic>::run(std::forward<Args>(args)...);
  }
}

template <int S>
struct SolveJob {
  static void run(const LobesInput& in, const SemiDiscretizationOptions& o,
                  std::vector<SpeedResult>& out) {
    solve_all<S>(in, o, out);
  }
};

template <int S>
struct GridJob {
  static void run(const LobesInput& in, const SemiDiscretizationOptions& o,
                  const std::vector<double>& depths_m, Eigen::MatrixXd& out) {
    grid_all<S>(in, o, depths_m, out);
  }
};

}  // namespace

LobesResult semi_discretization(const LobesInput& in, const SemiDiscretizationOptions& o) {
  validate(in);
  validate_options(o);
  validate_size(in, o);
  const auto start = std::chrono::steady_clock::now();
  LobesResult r;
  r.speeds.resize(in.spindle_rpm.size());
  by_size<SolveJob>(in.x_modes.size() + in.y_modes.size(), in, o, r.speeds);
  r.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.revolution_period = uses_revolution_period(in, o);
  r.summary.succeed();
  return r;
}

bool uses_revolution_period(const LobesInput& in, const SemiDiscretizationOptions& o) {
  return o.force_revolution_period || !equal_teeth(in);
}

Eigen::MatrixXd sd_spectral_radius_grid(const LobesInput& in, const SemiDiscretizationOptions& o,
                                        const std::vector<double>& depths_m) {
  validate(in);
  validate_options(o);
  validate_size(in, o);
  for (std::size_t j = 0; j < depths_m.size(); ++j) {
    require_rule(std::isfinite(depths_m[j]) && depths_m[j] >= 0.0,
                 "depths_m[" + std::to_string(j) + "]", depths_m[j], "must be finite and >= 0");
  }
  Eigen::MatrixXd out(static_cast<Eigen::Index>(in.spindle_rpm.size()),
                      static_cast<Eigen::Index>(depths_m.size()));
  by_size<GridJob>(in.x_modes.size() + in.y_modes.size(), in, o, depths_m, out);
  return out;
}

double sd_spectral_radius(const LobesInput& in, const SemiDiscretizationOptions& o,
                          double spindle_rpm, double depth_m) {
  validate(in);
  validate_options(o);
  validate_size(in, o);
  Kernel<Eigen::Dynamic> k(in, o);
  k.set_speed(spindle_rpm);
  return std::abs(k.critical_multiplier(depth_m));
}

}  // namespace lobes
}  // namespace chatterlab
