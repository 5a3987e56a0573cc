#include "analysis/grinding/grinding_synth.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/seed.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace grinding {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Uniform in [0, 1) from the top 53 bits (platform-independent, unlike
// std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

// Standard normal draws by Box-Muller on top-53-bit uniforms (unlike std::normal_distribution,
// the same on every platform); each pair of uniforms gives two normals, the second kept.
class NormalStream {
 public:
  explicit NormalStream(std::uint64_t seed) : rng_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform01(rng_);  // (0, 1]: log finite
    const double u2 = uniform01(rng_);
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(kTwoPi * u2);
    has_spare_ = true;
    return radius * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

[[noreturn]] void fail(const std::string& what) { throw InputError("grinding synth: " + what); }

void check_nonnegative(double v, const char* name) {
  if (!(std::isfinite(v) && v >= 0.0)) {
    std::ostringstream m;
    m << name << " = " << v << ": must be finite and >= 0";
    fail(m.str());
  }
}

void check_cycle(int c, int cycles, const char* name) {
  if (c < 1 || c > cycles) {
    std::ostringstream m;
    m << name << " names cycle " << c << ", outside 1.." << cycles;
    fail(m.str());
  }
}

bool contains(const std::vector<int>& v, int c) {
  return std::find(v.begin(), v.end(), c) != v.end();
}

void validate(const GrindingSeriesSpec& s) {
  if (s.cycles < 1) fail("cycles must be >= 1");
  if (!(std::isfinite(s.sample_period_s) && s.sample_period_s > 0.0))
    fail("sample_period_s must be finite and > 0");
  if (!s.cycle_schedules.empty() && s.cycle_schedules.size() != static_cast<std::size_t>(s.cycles))
    fail("cycle_schedules needs one schedule per cycle");
  if (!std::isfinite(s.ds_start_mm) || !std::isfinite(s.R0_start_um))
    fail("ds_start_mm and R0_start_um must be finite");
  check_nonnegative(s.R0_walk_var_um2, "R0_walk_var_um2");
  check_nonnegative(s.R0_cycle_var_um2, "R0_cycle_var_um2");
  for (double v : s.process_var) check_nonnegative(v, "process_var");
  check_nonnegative(s.power_sd_W, "power_sd_W");
  check_nonnegative(s.Dw_sd_mm, "Dw_sd_mm");
  check_nonnegative(s.ds_sd_mm, "ds_sd_mm");
  check_nonnegative(s.Ra_sd_um, "Ra_sd_um");
  check_nonnegative(s.roundness_sd_um, "roundness_sd_um");
  for (int c : s.uninspected_cycles) check_cycle(c, s.cycles, "uninspected_cycles");
  for (int c : s.ds_unmeasured_cycles) check_cycle(c, s.cycles, "ds_unmeasured_cycles");
  for (int c : s.Ra_unmeasured_cycles) check_cycle(c, s.cycles, "Ra_unmeasured_cycles");
  for (const auto& [c, a] : s.late) {
    check_cycle(c, s.cycles, "late");
    if (a < c) fail("late: available_cycle must be >= cycle");
    if (contains(s.uninspected_cycles, c)) fail("late names an uninspected cycle");
  }
  std::vector<int> dressed;
  for (const Dressing& d : s.dressings) {
    if (d.before_cycle < 2 || d.before_cycle > s.cycles)
      fail("dressing before_cycle must be in 2..cycles");
    if (!std::isfinite(d.depth_mm)) fail("dressing depth_mm must be finite");
    if (contains(dressed, d.before_cycle)) fail("several dressings before one cycle");
    dressed.push_back(d.before_cycle);
  }
}

}  // namespace

std::vector<double> expand_schedule(const std::vector<InfeedStage>& schedule) {
  std::vector<double> u;
  for (const InfeedStage& st : schedule) {
    if (st.rows < 0) fail("an infeed stage has rows < 0");
    if (!std::isfinite(st.u_mm_s)) fail("an infeed stage has a non-finite u_mm_s");
    u.insert(u.end(), static_cast<std::size_t>(st.rows), st.u_mm_s);
  }
  return u;
}

GrindingSeries synthesize_grinding_series(const GrindingSeriesSpec& spec) {
  validate(spec);
  const GrindingParameters& p = spec.truth;
  const int N = spec.cycles;

  // The commanded infeed of each cycle's propagation rows j = 0..n_i - 1.
  std::vector<std::vector<double>> u_cycle(static_cast<std::size_t>(N));
  GrindingSeries out;
  out.n.resize(static_cast<std::size_t>(N));
  Eigen::Index rows = 0;
  for (int i = 0; i < N; ++i) {
    const auto& sched = spec.cycle_schedules.empty()
                            ? spec.schedule
                            : spec.cycle_schedules[static_cast<std::size_t>(i)];
    u_cycle[static_cast<std::size_t>(i)] = expand_schedule(sched);
    const int n_i = static_cast<int>(u_cycle[static_cast<std::size_t>(i)].size());
    if (n_i < 1) fail("every cycle needs n_i >= 1 rows of propagation");
    out.n[static_cast<std::size_t>(i)] = n_i;
    rows += n_i + 1;
  }

  FastRecord& rec = out.record;
  rec.cycle.resize(static_cast<std::size_t>(rows));
  rec.u_mm_s.resize(rows);
  rec.power_W.resize(rows);
  rec.Dw_mm.resize(rows);
  out.truth_trajectory.resize(rows, 4);
  out.truth_at_cycle_end.resize(N, 4);
  out.Ra_true_um.resize(N);
  out.roundness_true_um.resize(N);

  NormalStream process_noise(derive_seed(spec.seed, "grinding.process", 0));
  NormalStream R0_noise(derive_seed(spec.seed, "grinding.R0", 0));
  NormalStream fast_noise(derive_seed(spec.seed, "grinding.fast", 0));
  NormalStream inspection_noise(derive_seed(spec.seed, "grinding.inspection", 0));
  const std::array<double, 3> process_sd{std::sqrt(spec.process_var[0]),
                                         std::sqrt(spec.process_var[1]),
                                         std::sqrt(spec.process_var[2])};
  const double R0_walk_sd = std::sqrt(spec.R0_walk_var_um2);
  const double R0_cycle_sd = std::sqrt(spec.R0_cycle_var_um2);

  // Truth X(1, 0) = (0, 0, d_s at the start, R0 at the start) (002 notes A9).
  ProcessState X(0.0, 0.0, spec.ds_start_mm, spec.R0_start_um);
  Eigen::Index row = 0;
  for (int i = 1; i <= N; ++i) {
    const std::vector<double>& u = u_cycle[static_cast<std::size_t>(i - 1)];
    const int n_i = out.n[static_cast<std::size_t>(i - 1)];
    if (i > 1) {
      // New cycle, no idle time: v restarts from 0; V'_w and d_s carry over (002 eq. 12); R0
      // takes its cycle-to-cycle step (002 sec. V).
      X[kV] = 0.0;
      X[kR0] += R0_cycle_sd * R0_noise();
      for (const Dressing& d : spec.dressings) {
        if (d.before_cycle != i) continue;
        X[kVw] = 0.0;  // V'_w counts the removal since the last dressing (D_w restarts)
        X[kDs] -= d.depth_mm;
      }
    }
    for (int j = 0; j <= n_i; ++j) {
      // Fast outputs of 002 eq. 9 (eq. 10 at j = n_i): P and D_w of appendix A plus noise.
      const Outputs y = outputs(X, p);
      rec.cycle[static_cast<std::size_t>(row)] = i;
      rec.u_mm_s[row] = j < n_i ? u[static_cast<std::size_t>(j)] : u.back();
      rec.power_W[row] = y[kPower] + spec.power_sd_W * fast_noise();
      rec.Dw_mm[row] = y[kDw] + spec.Dw_sd_mm * fast_noise();
      out.truth_trajectory.row(row) = X.transpose();
      ++row;
      if (j == n_i) break;
      // 002 eq. 8: X(i, j+1) = X + T_f F(X, u(i, j)) + eta, eta ~ N(0, diag(process_var,
      // R0_walk_var)).
      X = euler_step(X, u[static_cast<std::size_t>(j)], spec.sample_period_s, p);
      X[kVw] += process_sd[0] * process_noise();
      X[kV] += process_sd[1] * process_noise();
      X[kDs] += process_sd[2] * process_noise();
      X[kR0] += R0_walk_sd * R0_noise();
      if (X[kV] < 0.0) ++out.negative_v_steps;
    }
    // End of cycle (i, n_i): the truth and the inspection of 002 eq. 10.
    out.truth_at_cycle_end.row(i - 1) = X.transpose();
    const Outputs y = outputs(X, p);
    const double r = roundness_um(X, p);
    out.Ra_true_um[i - 1] = y[kRa];
    out.roundness_true_um[i - 1] = r;
    // Three draws per cycle whether or not the part is inspected.
    const double e_ds = spec.ds_sd_mm * inspection_noise();
    const double e_Ra = spec.Ra_sd_um * inspection_noise();
    const double e_r = spec.roundness_sd_um * inspection_noise();
    if (contains(spec.uninspected_cycles, i)) continue;
    Inspection ins;
    ins.cycle = i;
    ins.available_cycle = i;
    for (const auto& [c, a] : spec.late)
      if (c == i) ins.available_cycle = a;
    ins.ds_mm = contains(spec.ds_unmeasured_cycles, i) ? kNaN : y[kDsOut] + e_ds;
    ins.Ra_um = contains(spec.Ra_unmeasured_cycles, i) ? kNaN : y[kRa] + e_Ra;
    ins.roundness_um = std::isfinite(r) ? r + e_r : kNaN;
    out.inspections.push_back(ins);
  }
  return out;
}

}  // namespace grinding
}  // namespace chatterlab
