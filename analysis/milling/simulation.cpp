#include "analysis/milling/simulation.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/milling/chip_numerical.h"
#include "analysis/milling/chip_traditional.h"
#include "analysis/milling/engagement.h"
#include "analysis/milling/force_model.h"
#include "analysis/milling/inertial.h"
#include "analysis/milling/symplectic_euler.h"

namespace chatterlab {
namespace milling {

namespace {

void check_recording(const RecordingRequest& r, int revolutions) {
  const auto fail = [](const std::string& field, int value, const std::string& rule) {
    std::ostringstream m;
    m << "recording." << field << " = " << value << ": " << rule;
    throw InputError(m.str());
  };
  for (std::size_t i = 0; i < r.full_revolutions.size(); ++i) {
    const int j = r.full_revolutions[i];
    const std::string f = "full_revolutions[" + std::to_string(i) + "]";
    if (j < 0 || j >= revolutions) {
      fail(f, j, "must be in [0, " + std::to_string(revolutions - 1) + "] (the run's revolutions)");
    }
    for (std::size_t e = 0; e < i; ++e) {
      if (r.full_revolutions[e] == j) fail(f, j, "is requested twice");
    }
  }
  if (r.trace_revolutions < 0) fail("trace_revolutions", r.trace_revolutions, "must be >= 0");
  if (r.trace_revolutions > 0) {
    if (r.trace_first_revolution < 0 || r.trace_first_revolution >= revolutions) {
      fail("trace_first_revolution", r.trace_first_revolution,
           "must be in [0, " + std::to_string(revolutions - 1) + "]");
    }
    if (r.trace_revolutions > revolutions - r.trace_first_revolution) {
      fail("trace_revolutions", r.trace_revolutions,
           "runs past the last revolution (" + std::to_string(revolutions) + " in the run)");
    }
  }
}

RevolutionRecord make_record(int revolution, int S, int teeth) {
  RevolutionRecord r;
  r.revolution = revolution;
  r.first_step = static_cast<std::int64_t>(revolution) * S;
  for (Eigen::VectorXd* v :
       {&r.theta1_rad, &r.depth_m, &r.x_m, &r.y_m, &r.vx_m_s, &r.vy_m_s, &r.Fx_N, &r.Fy_N,
        &r.centrifugal_x_N, &r.centrifugal_y_N, &r.coriolis_x_N, &r.coriolis_y_N}) {
    v->setZero(S);
  }
  r.chip_m.setZero(S, teeth);
  return r;
}

// Forces of one step, at (x_j, theta_j).
struct StepForces {
  double Fx = 0.0, Fy = 0.0;           // cutting
  double cen_x = 0.0, cen_y = 0.0;     // centrifugal
  double cor_x = 0.0, cor_y = 0.0;     // Coriolis
  double ref_x = 0.0, ref_y = 0.0;     // spring reference (eccentricity)
  std::array<double, kMaxTeeth> chip;  // g_p w_p, written only when recording
};

class Stepper {
 public:
  Stepper(const SimulationOptions& o, const SimulationGrid& g, int sample_a)
      : o_(o),
        g_(g),
        geo_(tooth_path_geometry(o)),
        S_(g.steps_per_revolution),
        T_(g.steps_per_tooth),
        n_(g.teeth),
        ax_(symplectic_euler_axis(o.modal_x, g.time_step_s)),
        ay_(symplectic_euler_axis(o.modal_y ? *o.modal_y : o.modal_x, g.time_step_s)),
        window_(o.numerical, o.teeth, S_, o.feed_per_tooth_m),
        history_(S_, o.chip_model == ChipModel::kNumerical ? window_.history_steps_needed() : 1,
                 o.initial_deflection_m) {
    const EngagementWindow w = engagement_window(o.operation, o.radius_m, o.radial_immersion_m);
    mask_.assign(static_cast<std::size_t>(S_), 0u);
    for (int a = 0; a < S_; ++a) {
      std::uint32_t m = 0;
      for (int p = 1; p <= n_; ++p) {
        const int ap = (a + (p - 1) * T_) % S_;
        if (in_cut(ap * g.angle_step_rad, w.entry_rad, w.exit_rad)) m |= 1u << (p - 1);
      }
      mask_[static_cast<std::size_t>(a)] = m;
    }
    delay_x_.assign(static_cast<std::size_t>(T_), o.initial_deflection_m.x());
    delay_y_.assign(static_cast<std::size_t>(T_), o.initial_deflection_m.y());
    numerical_ = o.chip_model == ChipModel::kNumerical;
    angle_only_ = o.switching == SwitchingRule::kAngleOnly;
    inertial_ = o.inertial.enabled;
    eccentric_ = o.inertial.eccentricity_m > 0.0;
    every_step_ = numerical_ || inertial_ || eccentric_;
    mass_ = o.modal_x.m_kg;
    omega_ = o.spindle_rpm * kTwoPi / 60.0;
    const double c0 = std::cos(o.inertial.eccentricity_angle_rad);
    const double s0 = std::sin(o.inertial.eccentricity_angle_rad);
    ecc_cos0_ = o.inertial.eccentricity_m * c0;
    ecc_sin0_ = o.inertial.eccentricity_m * s0;
    surface_limit_ = geo_.original_surface_m - 1e-9 * o.radius_m;
    long_until_step_ =
        static_cast<std::int64_t>(std::llround(o.numerical.long_until_revolutions * S_));
    idle_run_vf_ = idle_runs(sample_a, 0);
    idle_run_pf_ = idle_runs(sample_a, 1);
    x_ = o.initial_deflection_m.x();
    y_ = o.initial_deflection_m.y();
  }

  // Runs steps of revolution j. Rec: full record (or nullptr); trace pointers (or nullptr).
  template <bool kRecord, EulerOrder kOrder>
  void revolution(int j, int sample_a, OncePerRevolution& samples, RevolutionRecord* rec, float* tx,
                  float* ty, double* mean_x, double* mean_y) {
    if constexpr (!kRecord) {
      if (!every_step_) {
        idle_skipping_revolution<kOrder>(j, sample_a, samples);
        return;
      }
    }
    std::int64_t k = static_cast<std::int64_t>(j) * S_;
    for (int a = 0; a < S_; ++a, ++k) {
      if constexpr (kOrder == EulerOrder::kVelocityFirst) forces<kRecord>(k, a, vx_, vy_, f_);
      if (a == sample_a) {
        samples.depth_m[j] = g_.depth_at_step(k);
        samples.x_m[j] = x_;
        samples.y_m[j] = y_;
      }
      if constexpr (kRecord) {
        if (rec) write_record(*rec, a, k);
        if (tx) {
          tx[a] = static_cast<float>(x_);
          ty[a] = static_cast<float>(y_);
          mean_x[a] += x_;
          mean_y[a] += y_;
        }
      }
      // Force-free steps take the same arithmetic as in idle_skipping_revolution, so a recorded
      // run is bit-identical to an unrecorded one.
      const bool free = !every_step_ && (kOrder == EulerOrder::kVelocityFirst
                                             ? idle_run_vf_
                                             : idle_run_pf_)[static_cast<std::size_t>(a)] > 0;
      if constexpr (kOrder == EulerOrder::kVelocityFirst) {
        if (free) {
          free_update(kOrder);
          continue;
        }
        ax_.kick(vx_, x_ - f_.ref_x, f_.Fx + f_.cen_x + f_.cor_x);
        ay_.kick(vy_, y_ - f_.ref_y, f_.Fy + f_.cen_y + f_.cor_y);
        ax_.drift(x_, vx_);
        ay_.drift(y_, vy_);
      } else {
        const int a1 = a + 1 == S_ ? 0 : a + 1;
        if (free) {
          free_update(kOrder);
          forces<kRecord>(k + 1, a1, vx_, vy_, f_);  // zero; clears the recorded chips
          continue;
        }
        ax_.drift(x_, vx_);
        ay_.drift(y_, vy_);
        forces<kRecord>(k + 1, a1, vx_, vy_, f_);
        ax_.kick(vx_, x_ - f_.ref_x, f_.Fx + f_.cen_x + f_.cor_x);
        ay_.kick(vy_, y_ - f_.ref_y, f_.Fy + f_.cen_y + f_.cor_y);
      }
    }
  }

  void free_update(EulerOrder order) {
    const FreeStep fx = free_step(ax_, order);
    const FreeStep fy = free_step(ay_, order);
    const double xn = fx.xx * x_ + fx.xv * vx_;
    vx_ = fx.vx * x_ + fx.vv * vx_;
    x_ = xn;
    const double yn = fy.xx * y_ + fy.xv * vy_;
    vy_ = fy.vx * y_ + fy.vv * vy_;
    y_ = yn;
  }

  // The traditional model without inertial forces has no force at most steps (no tooth in its
  // window, ~95 % of the steps at 0.382 mm immersion): those steps run in a tight loop, with
  // the same step written with both updates computed from the old state (the same map, 8
  // instead of ~20 cycles of dependent latency per step).
  template <EulerOrder kOrder>
  void idle_skipping_revolution(int j, int sample_a, OncePerRevolution& samples) {
    const std::vector<int>& idle_run =
        kOrder == EulerOrder::kVelocityFirst ? idle_run_vf_ : idle_run_pf_;
    const FreeStep fx = free_step(ax_, kOrder);
    const FreeStep fy = free_step(ay_, kOrder);
    std::int64_t k = static_cast<std::int64_t>(j) * S_;
    for (int a = 0; a < S_;) {
      if (a == sample_a) {
        samples.depth_m[j] = g_.depth_at_step(k);
        samples.x_m[j] = x_;
        samples.y_m[j] = y_;
      }
      const int run = idle_run[static_cast<std::size_t>(a)];
      if (run > 0) {
        // Same arithmetic as free_update(), on locals the compiler keeps in registers.
        double x = x_, vx = vx_, y = y_, vy = vy_;
        for (int i = 0; i < run; ++i) {
          const double xn = fx.xx * x + fx.xv * vx;
          vx = fx.vx * x + fx.vv * vx;
          x = xn;
          const double yn = fy.xx * y + fy.xv * vy;
          vy = fy.vx * y + fy.vv * vy;
          y = yn;
        }
        x_ = x, vx_ = vx, y_ = y, vy_ = vy;
        a += run;
        k += run;
        continue;
      }
      if constexpr (kOrder == EulerOrder::kVelocityFirst) {
        forces<false>(k, a, vx_, vy_, f_);
        ax_.kick(vx_, x_, f_.Fx);
        ay_.kick(vy_, y_, f_.Fy);
        ax_.drift(x_, vx_);
        ay_.drift(y_, vy_);
      } else {
        ax_.drift(x_, vx_);
        ay_.drift(y_, vy_);
        forces<false>(k + 1, a + 1 == S_ ? 0 : a + 1, vx_, vy_, f_);
        ax_.kick(vx_, x_, f_.Fx);
        ay_.kick(vy_, y_, f_.Fy);
      }
      ++a;
      ++k;
    }
  }

  // Position first evaluates the force of step 0 before the loop.
  void prime_position_first() { forces<true>(0, 0, vx_, vy_, f_); }

  double x() const { return x_; }
  double y() const { return y_; }
  const NumericalSearchStats& stats() const { return stats_; }

 private:
  void write_record(RevolutionRecord& r, int a, std::int64_t k) const {
    r.theta1_rad[a] = a * g_.angle_step_rad;
    r.depth_m[a] = g_.depth_at_step(k);
    r.x_m[a] = x_;
    r.y_m[a] = y_;
    r.vx_m_s[a] = vx_;
    r.vy_m_s[a] = vy_;
    for (int p = 0; p < n_; ++p) r.chip_m(a, p) = f_.chip[static_cast<std::size_t>(p)];
    r.Fx_N[a] = f_.Fx;
    r.Fy_N[a] = f_.Fy;
    r.centrifugal_x_N[a] = f_.cen_x;
    r.centrifugal_y_N[a] = f_.cen_y;
    r.coriolis_x_N[a] = f_.cor_x;
    r.coriolis_y_N[a] = f_.cor_y;
  }

  // A force-free step as a 2x2 map of (x, v): velocity first x' = x + h (a_v v + a_x x),
  // v' = a_v v + a_x x; position first x' = x + h v, v' = a_v v + a_x (x + h v).
  struct FreeStep {
    double xx, xv, vx, vv;
  };
  static FreeStep free_step(const SymplecticEulerAxis& s, EulerOrder order) {
    if (order == EulerOrder::kVelocityFirst) {
      return {1.0 + s.h * s.a_x, s.h * s.a_v, s.a_x, s.a_v};
    }
    return {1.0, s.h, s.a_x, s.a_v + s.a_x * s.h};
  }

  // idle_run[a]: number of consecutive force-free steps from angle index a on, stopping before
  // the sample index and the end of the revolution (position first: the force of step k + 1).
  std::vector<int> idle_runs(int sample_a, int shift) const {
    std::vector<int> run(static_cast<std::size_t>(S_) + 1, 0);
    for (int a = S_ - 1; a >= 0; --a) {
      const bool idle = mask_[static_cast<std::size_t>((a + shift) % S_)] == 0u && a != sample_a;
      run[static_cast<std::size_t>(a)] = idle ? run[static_cast<std::size_t>(a) + 1] + 1 : 0;
    }
    return run;
  }

  // Adds tooth p's force for chip w (already decided: cutting or angle-only window).
  void add_tooth(int p, int ap, double w, double b, bool signed_chip, StepForces& f) const {
    const CuttingCoefficients& K = o_.coefficients[static_cast<std::size_t>(p - 1)];
    const ToothForce tf =
        signed_chip ? tooth_force_signed(K, w, b, true) : tooth_force(K, w, b, true);
    const Eigen::Vector2d xy = tooth_force_xy_N(tf, geo_.sin_theta[static_cast<std::size_t>(ap)],
                                                geo_.cos_theta[static_cast<std::size_t>(ap)]);
    f.Fx += xy.x();
    f.Fy += xy.y();
  }

  // Forces of step k at angle index a from the current position and velocity (vx, vy).
  template <bool kRecord>
  void forces(std::int64_t k, int a, double vx, double vy, StepForces& f) {
    f.Fx = f.Fy = 0.0;
    if constexpr (kRecord) std::fill(f.chip.begin(), f.chip.begin() + n_, 0.0);
    if (!every_step_) {
      const std::uint32_t m = mask_[static_cast<std::size_t>(a)];
      if (m == 0u) return;
      traditional<kRecord>(k, a, m, f);
      return;
    }
    if (numerical_) {
      numerical<kRecord>(k, a, f);
    } else {
      const std::uint32_t m = mask_[static_cast<std::size_t>(a)];
      if (m != 0u) traditional<kRecord>(k, a, m, f);
    }
    if (inertial_) {
      const InertialForces in =
          inertial_forces(Eigen::Vector2d(x_, y_), Eigen::Vector2d(vx, vy), mass_, omega_);
      f.cen_x = in.centrifugal_N.x();
      f.cen_y = in.centrifugal_N.y();
      f.cor_x = in.coriolis_N.x();
      f.cor_y = in.coriolis_N.y();
    }
    if (eccentric_) {
      // r0 (sin(theta - theta0), cos(theta - theta0)) with theta = theta_1 (000 eqs 7.8-7.9).
      const double s = geo_.sin_theta[static_cast<std::size_t>(a)];
      const double c = geo_.cos_theta[static_cast<std::size_t>(a)];
      f.ref_x = s * ecc_cos0_ - c * ecc_sin0_;
      f.ref_y = c * ecc_cos0_ + s * ecc_sin0_;
    }
  }

  template <bool kRecord>
  void traditional(std::int64_t k, int a, std::uint32_t mask, StepForces& f) {
    // x(t - tau): the delay buffer holds the deflection of the same phase one tooth pass ago.
    const int s = a % T_;
    const double dx = x_ - delay_x_[static_cast<std::size_t>(s)];
    const double dy = y_ - delay_y_[static_cast<std::size_t>(s)];
    delay_x_[static_cast<std::size_t>(s)] = x_;
    delay_y_[static_cast<std::size_t>(s)] = y_;
    const double b = g_.depth_at_step(k);
    for (int p = 1; p <= n_; ++p) {
      if (!(mask & (1u << (p - 1)))) continue;
      int ap = a + (p - 1) * T_;
      if (ap >= S_) ap -= S_;
      const double w = chip_thickness_traditional(
          o_.feed_per_tooth_m, geo_.sin_theta[static_cast<std::size_t>(ap)],
          geo_.cos_theta[static_cast<std::size_t>(ap)], dx, dy);
      if (angle_only_) {
        add_tooth(p, ap, w, b, true, f);
        if constexpr (kRecord) f.chip[static_cast<std::size_t>(p - 1)] = w;
      } else if (w > 0.0) {
        add_tooth(p, ap, w, b, false, f);
        if constexpr (kRecord) f.chip[static_cast<std::size_t>(p - 1)] = w;
      }
    }
  }

  template <bool kRecord>
  void numerical(std::int64_t k, int a, StepForces& f) {
    window_.observe(k, Eigen::Vector2d(x_ - history_.x(k - S_), y_ - history_.y(k - S_)));
    const std::int64_t W = window_.window_steps(k);
    if (W == window_.long_window_steps() && k >= long_until_step_) ++stats_.long_window_steps;
    const double b = g_.depth_at_step(k);
    const double side_y = geo_.side * y_;
    for (int p = 1; p <= n_; ++p) {
      int ap = a + (p - 1) * T_;
      if (ap >= S_) ap -= S_;
      // Cheap pre-test, slightly looser than the search's own "tip beyond the original surface".
      if (!(side_y + geo_.side * o_.radius_m * geo_.cos_theta[static_cast<std::size_t>(ap)] >
            surface_limit_)) {
        continue;
      }
      ChipSearchQuery q;
      q.step = k;
      q.tooth = p;
      q.deflection_m = Eigen::Vector2d(x_, y_);
      q.window_steps = W;
      const ChipSearchResult r = o_.numerical.fast_search ? chip_numerical_fast(geo_, history_, q)
                                                          : chip_numerical_plain(geo_, history_, q);
      ++stats_.searches;
      stats_.points += r.points;
      if (r.cutting) {
        add_tooth(p, ap, r.chip_m, b, false, f);
        if constexpr (kRecord) f.chip[static_cast<std::size_t>(p - 1)] = r.chip_m;
      }
    }
    history_.push(x_, y_);
  }

  const SimulationOptions& o_;
  const SimulationGrid& g_;
  ToothPathGeometry geo_;
  int S_, T_, n_;
  SymplecticEulerAxis ax_, ay_;
  SearchWindowRule window_;
  ToothPathHistory history_;
  std::vector<std::uint32_t> mask_;        // bit p-1: tooth p in the engagement window at angle a
  std::vector<double> delay_x_, delay_y_;  // traditional model, by phase a mod T
  std::vector<int> idle_run_vf_, idle_run_pf_;
  bool numerical_ = false, angle_only_ = false, inertial_ = false, eccentric_ = false;
  bool every_step_ = false;
  double mass_ = 0.0, omega_ = 0.0, ecc_cos0_ = 0.0, ecc_sin0_ = 0.0;
  double surface_limit_ = 0.0;
  std::int64_t long_until_step_ = 0;
  double x_ = 0.0, y_ = 0.0, vx_ = 0.0, vy_ = 0.0;
  StepForces f_{};
  NumericalSearchStats stats_;
};

}  // namespace

SimulationResult simulate(const SimulationOptions& options, const RecordingRequest& recording) {
  const SimulationGrid g = simulation_grid(options);  // validates
  check_recording(recording, g.revolutions);
  const int S = g.steps_per_revolution;

  SimulationResult result;
  result.time_step_s = g.time_step_s;
  result.steps_per_revolution = S;
  double wrapped = std::fmod(options.sample_angle_rad, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  const int sample_a = static_cast<int>(std::llround(wrapped / g.angle_step_rad)) % S;
  result.samples.angle_rad = sample_a * g.angle_step_rad;
  result.samples.depth_m.setConstant(g.revolutions, std::numeric_limits<double>::quiet_NaN());
  result.samples.x_m.setConstant(g.revolutions, std::numeric_limits<double>::quiet_NaN());
  result.samples.y_m.setConstant(g.revolutions, std::numeric_limits<double>::quiet_NaN());

  // Everything the loop writes is allocated here.
  std::vector<int> record_of(static_cast<std::size_t>(g.revolutions), -1);
  result.records.reserve(recording.full_revolutions.size());
  for (std::size_t i = 0; i < recording.full_revolutions.size(); ++i) {
    const int j = recording.full_revolutions[i];
    result.records.push_back(make_record(j, S, options.teeth));
    record_of[static_cast<std::size_t>(j)] = static_cast<int>(i);
  }
  CompactTrace& trace = result.trace;
  trace.first_revolution = recording.trace_first_revolution;
  trace.revolutions = recording.trace_revolutions;
  const std::size_t trace_len = static_cast<std::size_t>(recording.trace_revolutions) * S;
  trace.x_m.assign(trace_len, 0.0f);
  trace.y_m.assign(trace_len, 0.0f);
  if (recording.trace_revolutions > 0) {
    trace.angle_rad = Eigen::VectorXd::LinSpaced(S, 0.0, (S - 1) * g.angle_step_rad);
    trace.mean_x_m.setZero(S);
    trace.mean_y_m.setZero(S);
  }

  Stepper stepper(options, g, sample_a);
  const bool vf = options.euler_order == EulerOrder::kVelocityFirst;
  if (!vf) stepper.prime_position_first();
  const auto t0 = std::chrono::steady_clock::now();
  int done = 0;
  bool diverged = false;
  for (int j = 0; j < g.revolutions; ++j) {
    const int ri = record_of[static_cast<std::size_t>(j)];
    RevolutionRecord* rec = ri >= 0 ? &result.records[static_cast<std::size_t>(ri)] : nullptr;
    float* tx = nullptr;
    float* ty = nullptr;
    const int tj = j - trace.first_revolution;
    if (tj >= 0 && tj < trace.revolutions) {
      tx = trace.x_m.data() + static_cast<std::size_t>(tj) * S;
      ty = trace.y_m.data() + static_cast<std::size_t>(tj) * S;
    }
    double* mx = tx ? trace.mean_x_m.data() : nullptr;
    double* my = tx ? trace.mean_y_m.data() : nullptr;
    if (rec || tx) {
      if (vf) {
        stepper.revolution<true, EulerOrder::kVelocityFirst>(j, sample_a, result.samples, rec, tx,
                                                             ty, mx, my);
      } else {
        stepper.revolution<true, EulerOrder::kPositionFirst>(j, sample_a, result.samples, rec, tx,
                                                             ty, mx, my);
      }
    } else if (vf) {
      stepper.revolution<false, EulerOrder::kVelocityFirst>(j, sample_a, result.samples, nullptr,
                                                            nullptr, nullptr, nullptr, nullptr);
    } else {
      stepper.revolution<false, EulerOrder::kPositionFirst>(j, sample_a, result.samples, nullptr,
                                                            nullptr, nullptr, nullptr, nullptr);
    }
    done = j + 1;
    if (!(std::abs(stepper.x()) <= options.radius_m && std::abs(stepper.y()) <= options.radius_m)) {
      std::ostringstream m;
      m << "deflection left the tool radius (|x| or |y| > " << options.radius_m
        << " m) in revolution " << j << " at depth "
        << g.depth_at_step(static_cast<std::int64_t>(j) * S)
        << " m: the model broke down (diverging vibration)";
      result.summary.fail(m.str());
      diverged = true;
      break;
    }
  }
  result.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.revolutions = done;
  result.steps = static_cast<std::int64_t>(done) * S;
  result.numerical = stepper.stats();
  const int traced = std::clamp(done - trace.first_revolution, 0, trace.revolutions);
  if (traced > 0) {
    trace.mean_x_m /= traced;
    trace.mean_y_m /= traced;
  }
  if (!diverged) result.summary.succeed();
  return result;
}

}  // namespace milling
}  // namespace chatterlab
