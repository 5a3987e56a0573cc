#include "analysis/grinding/multirate_ekf.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "analysis/common/check.h"
#include "analysis/kalman/extended_kalman_filter.h"

namespace chatterlab {
namespace grinding {
namespace {

constexpr int kMeasurements = 4;  // P, D_w, d_s, R_a (OutputIndex)
using Mask = kalman::MeasurementMask<kMeasurements>;

// The process and measurement model of the filter with N = 3 (x1..x3; R0 held at its nominal
// value, used by no update) or N = 4 (x1..x3, R0) states, in the interface of
// kalman::ExtendedKalmanFilter.
template <int N>
struct FilterModel {
  static constexpr int kStates = N;
  static constexpr int kMeasurements = grinding::kMeasurements;
  using State = kalman::Matrix<N, 1>;
  using Measurement = kalman::Matrix<kMeasurements, 1>;
  using Input = double;  // u of row j - 1, mm/s

  const GrindingParameters* p = nullptr;
  double wear_k = 0.0;  // wear_constant(*p), once
  double T_f_s = 0.02;
  State q = State::Zero();  // Q: diagonal, added once per fast step (format section 7)
  kalman::Matrix<kMeasurements, kMeasurements> R =
      kalman::Matrix<kMeasurements, kMeasurements>::Zero();

  ProcessState full(const State& x) const {
    ProcessState X;
    X.template head<N>() = x;
    if constexpr (N == 3) X[kR0] = p->R0_um;
    return X;
  }

  // 002 eq. 8 and A = I + T_f dF/dX of eq. 14.
  State propagate(const State& x, const Input& u, kalman::Matrix<N, N>* F) const {
    Eigen::Matrix4d A;
    const ProcessState next =
        euler_step(full(x), u, T_f_s, *p, wear_k, F != nullptr ? &A : nullptr);
    if (F != nullptr) *F = A.template topLeftCorner<N, N>();
    return next.template head<N>();
  }
  void add_process_noise(const State&, kalman::Matrix<N, N>* P) const { P->diagonal() += q; }
  Measurement measure(const State& x, kalman::Matrix<kMeasurements, N>* H) const {
    Eigen::Matrix4d Hfull;
    const Outputs y = outputs(full(x), *p, H != nullptr ? &Hfull : nullptr);
    if (H != nullptr) *H = Hfull.template leftCols<N>();
    return y;
  }
  const kalman::Matrix<kMeasurements, kMeasurements>& measurement_noise() const { return R; }
};

struct CycleRows {
  int cycle = 0;           // 1-based cycle number
  Eigen::Index first = 0;  // record row of j = 0
  int n = 0;               // n_i: the cycle's rows are j = 0..n
};

std::vector<CycleRows> cycles_of(const FastRecord& r) {
  std::vector<CycleRows> out;
  for (std::size_t k = 0; k < r.cycle.size(); ++k) {
    if (out.empty() || r.cycle[k] != out.back().cycle) {
      out.push_back({r.cycle[k], static_cast<Eigen::Index>(k), 0});
    } else {
      ++out.back().n;
    }
  }
  return out;
}

template <int N>
class SeriesFilter {
 public:
  using Model = FilterModel<N>;
  using Filter = kalman::ExtendedKalmanFilter<Model>;
  using State = typename Model::State;
  using Cov = kalman::Matrix<N, N>;

  SeriesFilter(const GrindingEstimatorInfo& info, const GrindingParameters& p,
               const GrindingFilterSettings& s, const FastRecord& record,
               const std::vector<Inspection>& inspections, const std::vector<Dressing>& dressings,
               GrindingRun& out)
      : info_(info),
        p_(p),
        s_(s),
        record_(record),
        cycles_(cycles_of(record)),
        filter_(model(p, s), start_state(p), start_covariance(s),
                kalman::FilterOptions{s.joseph ? kalman::CovarianceUpdate::kJoseph
                                               : kalman::CovarianceUpdate::kStandard}),
        out_(out) {
    for (const Inspection& i : inspections) inspection_[i.cycle] = i;
    for (const Dressing& d : dressings) dressing_[d.before_cycle] = d;
    prior_end_x_.resize(cycles_.size());
    prior_end_P_.resize(cycles_.size());
    counted_.assign(cycles_.size(), false);
    inspection_nis_.assign(cycles_.size(), kalman::Innovation{});
    fast_nis_sum_.assign(cycles_.size(), 0.0);
    fast_nis_dof_.assign(cycles_.size(), 0);
  }

  void run() {
    out_.states = N;
    std::size_t rows = 0;
    for (const CycleRows& c : cycles_) rows += static_cast<std::size_t>(c.n) + 1;
    out_.trajectory.reserve(rows);
    out_.per_cycle.reserve(cycles_.size());
    for (std::size_t c = 0; c < cycles_.size(); ++c) {
      if (c > 0) new_cycle(c);
      rows_to_end(c, /*live=*/true);
      // Inspections that become usable at this cycle's end for earlier cycles (late): applied
      // at their own cycle ends, the rows since replayed (format section 7, "late results").
      const std::size_t first_late = earliest_late_arrival(c);
      if (first_late < c) replay(first_late, c);
      CycleEstimate e;
      const State& x = filter_.state();
      const Cov& P = filter_.covariance();
      e.ds_prior_mm = x[kDs];
      e.ds_prior_3sigma_mm = 3.0 * std::sqrt(std::max(P(kDs, kDs), 0.0));
      if (info_.estimates_R0) e.Ra_pred_um = filter_.model().measure(x, nullptr)[kRa];
      e.inspected = end_update(c, cycles_[c].cycle, /*live=*/true);
      e.posterior = estimate(cycles_[c].cycle, cycles_[c].n);
      e.covariance.setZero();
      e.covariance.template topLeftCorner<N, N>() = filter_.covariance();
      out_.trajectory.push_back(e.posterior);
      out_.per_cycle.push_back(e);
      ++out_.steps;
    }
    for (std::size_t c = 0; c < cycles_.size(); ++c) {  // late inspections' NIS known now
      CycleEstimate& e = out_.per_cycle[c];
      e.nis_fast_dof = fast_nis_dof_[c];
      if (fast_nis_dof_[c] > 0) e.nis_fast_per_dof = fast_nis_sum_[c] / fast_nis_dof_[c];
      e.nis_inspection_dof = inspection_nis_[c].dimension;
      if (inspection_nis_[c].dimension > 0) {
        e.nis_inspection_per_dof = inspection_nis_[c].nis / inspection_nis_[c].dimension;
      }
    }
  }

 private:
  static Model model(const GrindingParameters& p, const GrindingFilterSettings& s) {
    Model m;
    m.p = &p;
    m.wear_k = wear_constant(p);
    m.T_f_s = s.sample_period_s;
    for (int i = 0; i < N; ++i) m.q[i] = s.Q[static_cast<std::size_t>(i)];
    m.R.setZero();
    m.R(kPower, kPower) = s.power_sd_W * s.power_sd_W;
    m.R(kDw, kDw) = s.Dw_sd_mm * s.Dw_sd_mm;
    m.R(kDsOut, kDsOut) = s.ds_sd_mm * s.ds_sd_mm;
    m.R(kRa, kRa) = s.Ra_sd_um * s.Ra_sd_um;
    return m;
  }
  static State start_state(const GrindingParameters& p) {
    State x;
    x[kVw] = 0.0;
    x[kV] = 0.0;
    x[kDs] = p.ds0_mm;
    if constexpr (N == 4) x[kR0] = p.R0_um;
    return x;
  }
  static Cov start_covariance(const GrindingFilterSettings& s) {
    Cov P = Cov::Zero();
    for (int i = 0; i < N; ++i) P(i, i) = s.P0[static_cast<std::size_t>(i)];
    return P;
  }

  GrindingEstimate estimate(int cycle, int j) const {
    GrindingEstimate e;
    e.cycle = cycle;
    e.j = j;
    const State& x = filter_.state();
    const Cov& P = filter_.covariance();
    for (int i = 0; i < N; ++i) {
      e.x[i] = x[i];
      e.three_sigma[i] = 3.0 * std::sqrt(std::max(P(i, i), 0.0));
    }
    return e;
  }

  typename Model::Measurement fast_measurement(Eigen::Index row) const {
    typename Model::Measurement z = Model::Measurement::Zero();
    z[kPower] = record_.power_W[row];
    z[kDw] = record_.Dw_mm[row];
    return z;
  }

  // Rows j = 0..n-1 of cycle c with their fast updates, then the propagation to (c, n); the
  // a priori state there is stored. live: the first time (trajectory and NIS recorded).
  void rows_to_end(std::size_t c, bool live) {
    const CycleRows& cy = cycles_[c];
    Mask fast;
    fast.set(kPower).set(kDw);
    for (int j = 0; j <= cy.n; ++j) {
      const Eigen::Index row = cy.first + j;
      if (j > 0) filter_.predict(record_.u_mm_s[row - 1]);
      if (j == cy.n) break;
      const kalman::Innovation in = filter_.update(fast_measurement(row), fast);
      if (live) {
        count_fast(c, in);
        out_.trajectory.push_back(estimate(cy.cycle, j));
        ++out_.steps;
      } else {
        ++out_.replayed_steps;
      }
    }
    prior_end_x_[c] = filter_.state();
    prior_end_P_[c] = filter_.covariance();
  }

  void count_fast(std::size_t c, const kalman::Innovation& in) {
    out_.nis_fast_sum += in.nis;
    out_.nis_fast_dof += in.dimension;
    fast_nis_sum_[c] += in.nis;
    fast_nis_dof_[c] += in.dimension;
  }

  // The inspection rows of cycle c usable by the end of cycle `usable_by` (a cycle number).
  Mask inspection_rows(std::size_t c, int usable_by) const {
    Mask m;
    const auto it = inspection_.find(cycles_[c].cycle);
    if (it == inspection_.end() || it->second.available_cycle > usable_by) return m;
    if (info_.uses_ds && std::isfinite(it->second.ds_mm)) m.set(kDsOut);
    if (info_.uses_Ra && std::isfinite(it->second.Ra_um)) m.set(kRa);
    return m;
  }

  // The joint update of eqs 17-18 at (c, n_c) with the inspection values usable by the end of
  // cycle `usable_by`. Returns whether it held any.
  bool end_update(std::size_t c, int usable_by, bool live) {
    const Eigen::Index row = cycles_[c].first + cycles_[c].n;
    typename Model::Measurement z = fast_measurement(row);
    const Mask slow = inspection_rows(c, usable_by);
    if (slow.any()) {
      const Inspection& i = inspection_.at(cycles_[c].cycle);
      if (slow.test(kDsOut)) z[kDsOut] = i.ds_mm;
      if (slow.test(kRa)) z[kRa] = i.Ra_um;
    }
    Mask rows = slow;
    rows.set(kPower).set(kDw);
    const kalman::Innovation in = filter_.update(z, rows);
    if (slow.any()) {
      if (!counted_[c]) {  // each update holding inspection values counted once
        out_.nis_end_sum += in.nis;
        out_.nis_end_dof += in.dimension;
        inspection_nis_[c] = in;
        counted_[c] = true;
      }
    } else if (live) {
      count_fast(c, in);
    }
    return slow.any();
  }

  // The earliest cycle before c whose inspection (with a value this estimator uses) becomes
  // usable at the end of c; c when none.
  std::size_t earliest_late_arrival(std::size_t c) const {
    for (std::size_t b = 0; b < c; ++b) {
      const auto it = inspection_.find(cycles_[b].cycle);
      if (it == inspection_.end() || it->second.available_cycle != cycles_[c].cycle) continue;
      if (inspection_rows(b, cycles_[c].cycle).any()) return b;
    }
    return c;
  }

  // From the stored a priori state at (b, n_b): the end update with everything usable by the
  // end of cycle a, then the rows of cycles b+1..a replayed to the a priori state at (a, n_a).
  void replay(std::size_t b, std::size_t a) {
    const int usable_by = cycles_[a].cycle;
    filter_.set_state(prior_end_x_[b], prior_end_P_[b]);
    end_update(b, usable_by, /*live=*/false);
    for (std::size_t c = b + 1; c <= a; ++c) {
      new_cycle(c);
      rows_to_end(c, /*live=*/false);
      if (c < a) end_update(c, usable_by, /*live=*/false);
    }
  }

  // The transition into cycle c (format section 7, "new cycle"; 002 eqs 12-13).
  void new_cycle(std::size_t c) {
    State x = filter_.state();
    Cov P = filter_.covariance();
    x[kV] = 0.0;  // v restarts from 0
    P.row(kV).setZero();
    P.col(kV).setZero();
    P(kV, kV) = s_.P0[kV];
    if constexpr (N == 4) P(kR0, kR0) += s_.R0_cycle_var_um2;
    const auto d = dressing_.find(cycles_[c].cycle);
    if (d != dressing_.end()) {
      x[kVw] = 0.0;  // removal counted from the dressing
      P.row(kVw).setZero();
      P.col(kVw).setZero();
      P(kVw, kVw) = s_.P0[kVw];
      x[kDs] -= d->second.depth_mm;
      P(kDs, kDs) += s_.dress_sd_mm * s_.dress_sd_mm;
    }
    filter_.set_state(x, P);
  }

  const GrindingEstimatorInfo& info_;
  const GrindingParameters& p_;
  const GrindingFilterSettings& s_;
  const FastRecord& record_;
  std::vector<CycleRows> cycles_;
  Filter filter_;
  GrindingRun& out_;
  std::map<int, Inspection> inspection_;  // by cycle
  std::map<int, Dressing> dressing_;      // by before_cycle
  std::vector<State> prior_end_x_;
  std::vector<Cov> prior_end_P_;
  std::vector<bool> counted_;  // an update holding this cycle's inspection was counted
  std::vector<kalman::Innovation> inspection_nis_;  // that update's NIS, per cycle
  std::vector<double> fast_nis_sum_;                // live updates without inspections
  std::vector<int> fast_nis_dof_;
};

}  // namespace

const GrindingEstimatorInfo& estimator_info(GrindingEstimatorId id) {
  for (const auto& e : kGrindingEstimators) {
    if (e.id == id) return e;
  }
  CHATTERLAB_CHECK(false, "unknown grinding estimator id");
  return kGrindingEstimators[0];
}

double GrindingRun::nis_fast_per_dof() const {
  return nis_fast_dof > 0 ? nis_fast_sum / nis_fast_dof : std::numeric_limits<double>::quiet_NaN();
}

double GrindingRun::nis_end_per_dof() const {
  return nis_end_dof > 0 ? nis_end_sum / nis_end_dof : std::numeric_limits<double>::quiet_NaN();
}

void check_series(const FastRecord& r, const std::vector<Inspection>& inspections,
                  const std::vector<Dressing>& dressings) {
  const auto n = static_cast<Eigen::Index>(r.cycle.size());
  if (r.u_mm_s.size() != n || r.power_W.size() != n || r.Dw_mm.size() != n) {
    throw InputError("the channels cycle, u_mm_s, power and Dw_mm differ in length");
  }
  if (n == 0) throw InputError("the fast record has no rows");
  const std::vector<CycleRows> cycles = cycles_of(r);
  for (std::size_t k = 0; k < cycles.size(); ++k) {
    if (cycles[k].cycle != static_cast<int>(k) + 1) {
      throw InputError(
          "cycle: cycles must be 1..N, each cycle's rows contiguous and in order (row " +
          std::to_string(cycles[k].first + 1) + " has cycle " + std::to_string(cycles[k].cycle) +
          ", expected " + std::to_string(k + 1) + ")");
    }
    if (cycles[k].n < 1) {
      throw InputError("cycle " + std::to_string(cycles[k].cycle) +
                       " has one row: a cycle needs at least two (j = 0 and its end)");
    }
  }
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!std::isfinite(r.u_mm_s[k]) || !std::isfinite(r.power_W[k]) || !std::isfinite(r.Dw_mm[k])) {
      throw InputError("row " + std::to_string(k + 1) +
                       ": u_mm_s, power and Dw_mm must be finite numbers");
    }
  }
  const int N = static_cast<int>(cycles.size());
  std::map<int, int> seen;
  for (const Inspection& i : inspections) {
    if (i.cycle < 1 || i.cycle > N) {
      throw InputError("inspections: cycle " + std::to_string(i.cycle) + " is not in 1.." +
                       std::to_string(N));
    }
    if (i.available_cycle < i.cycle) {
      throw InputError("inspections: cycle " + std::to_string(i.cycle) + ": available_cycle " +
                       std::to_string(i.available_cycle) + " is before the cycle");
    }
    if (++seen[i.cycle] > 1) {
      throw InputError("inspections: cycle " + std::to_string(i.cycle) + " has more than one row");
    }
  }
  std::map<int, int> dressed;
  for (const Dressing& d : dressings) {
    if (d.before_cycle < 2 || d.before_cycle > N) {
      throw InputError("dressings: before_cycle " + std::to_string(d.before_cycle) +
                       " is not in 2.." + std::to_string(N));
    }
    if (!(d.depth_mm >= 0.0)) throw InputError("dressings: depth_mm must be >= 0");
    if (++dressed[d.before_cycle] > 1) {
      throw InputError("dressings: two dressings before cycle " + std::to_string(d.before_cycle));
    }
  }
}

GrindingRun run_grinding_estimator(GrindingEstimatorId id, const GrindingParameters& p,
                                   const GrindingFilterSettings& s, const FastRecord& record,
                                   const std::vector<Inspection>& inspections,
                                   const std::vector<Dressing>& dressings) {
  check_series(record, inspections, dressings);
  GrindingRun out;
  out.id = id;
  const GrindingEstimatorInfo& info = estimator_info(id);
  if (info.estimates_R0) {
    SeriesFilter<4>(info, p, s, record, inspections, dressings, out).run();
  } else {
    SeriesFilter<3>(info, p, s, record, inspections, dressings, out).run();
  }
  for (const CycleEstimate& c : out.per_cycle) {
    if (!c.posterior.x.head(out.states).allFinite()) {
      out.summary.fail("the estimate diverged (not finite) by the end of cycle " +
                       std::to_string(c.posterior.cycle));
      return out;
    }
  }
  out.summary.succeed();
  return out;
}

double nees_per_dof(const GrindingRun& run, const Eigen::MatrixX4d& truth) {
  if (!run.summary.ok() || truth.rows() != static_cast<Eigen::Index>(run.per_cycle.size())) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const int n = run.states;
  double sum = 0.0;
  for (std::size_t i = 0; i < run.per_cycle.size(); ++i) {
    const CycleEstimate& c = run.per_cycle[i];
    const Eigen::VectorXd e =
        c.posterior.x.head(n) - truth.row(static_cast<Eigen::Index>(i)).transpose().head(n);
    const Eigen::MatrixXd P = c.covariance.topLeftCorner(n, n);
    sum += e.dot(P.ldlt().solve(e)) / n;
  }
  return sum / static_cast<double>(run.per_cycle.size());
}

}  // namespace grinding
}  // namespace chatterlab
