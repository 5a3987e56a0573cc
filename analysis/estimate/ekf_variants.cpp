#include "analysis/estimate/ekf_variants.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "analysis/common/require.h"
#include "analysis/estimate/ekf.h"
#include "analysis/kalman/unscented_kalman_filter.h"

namespace chatterlab {
namespace estimate {

namespace {

void require_coefficients(const std::vector<ToothCoefficients>& c, const std::string& name) {
  for (std::size_t i = 0; i < c.size(); ++i) {
    const std::string f = name + "[" + std::to_string(i) + "]";
    require_rule(std::isfinite(c[i].Kt_N_m2), f + ".Kt_N_m2", c[i].Kt_N_m2, "must be finite");
    require_rule(std::isfinite(c[i].Kr_N_m2), f + ".Kr_N_m2", c[i].Kr_N_m2, "must be finite");
  }
}

// Decimated history: the initial estimate, every stride-th step and the last step.
class HistoryRecorder {
 public:
  HistoryRecorder(std::vector<std::string> columns, std::int64_t steps, int points) {
    stride_ = std::max<std::int64_t>(1, (steps + points - 2) / (points - 1));
    const std::int64_t rows = 1 + steps / stride_ + (steps % stride_ != 0 ? 1 : 0);
    h_.columns = std::move(columns);
    h_.time_s.resize(rows);
    h_.values.resize(rows, static_cast<Eigen::Index>(h_.columns.size()));
    last_ = steps;
  }
  // Step s (1-based: s filter steps done; 0 = the initial estimate).
  bool due(std::int64_t s) const { return s % stride_ == 0 || s == last_; }
  template <typename Row>
  void record(double time_s, const Row& row) {
    h_.time_s[row_] = time_s;
    h_.values.row(row_) = row.transpose();
    ++row_;
  }
  EstimateHistory take() {
    h_.time_s.conservativeResize(row_);
    h_.values.conservativeResize(row_, h_.values.cols());
    return std::move(h_);
  }

 private:
  EstimateHistory h_;
  std::int64_t stride_ = 1;
  std::int64_t last_ = 0;
  Eigen::Index row_ = 0;
};

std::vector<std::string> deflection_columns(bool y_axis) {
  if (y_axis) return {"x_m", "vx_m_s", "y_m", "vy_m_s"};
  return {"x_m", "vx_m_s"};
}

// History columns: the deflection states, then the estimate keys (kEstimators).
std::vector<std::string> state_columns(EstimatorId id, int teeth) {
  std::vector<std::string> c = deflection_columns(estimator_info(id).measured_axes == 2);
  for (std::string& k : estimate_keys(id, teeth)) c.push_back(std::move(k));
  return c;
}

constexpr bool same_text(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) {
    ++a;
    ++b;
  }
  return *a == *b;
}

// The table row of `id` describes Model: states, measured axes, and the estimate keys in the
// order of the model's parameter states.
template <class Model>
constexpr bool row_matches_model(EstimatorId id) {
  const EstimatorInfo& e = estimator_info(id);
  const auto key_is = [&e](int state, const char* key) {
    return state < 0 ||
           same_text(e.keys[static_cast<std::size_t>(state - Model::kFirstParameter)], key);
  };
  return e.states == Model::kStates && e.measured_axes == Model::kMeasurements &&
         e.key_count == Model::kParameters && key_is(Model::kMass, "m_kg") &&
         key_is(Model::kDamping, "c_kg_s") && key_is(Model::kStiffness, "k_N_m");
}
static_assert(row_matches_model<ModalXModel>(EstimatorId::kModalX));
static_assert(row_matches_model<ModalXyModel>(EstimatorId::kModalXy));
static_assert(row_matches_model<ModalXyMkModel>(EstimatorId::kModalXyMk));
static_assert(row_matches_model<ModalXyMcModel>(EstimatorId::kModalXyMc));
static_assert(row_matches_model<CoeffXyModel>(EstimatorId::kCoeffXy));
static_assert(row_matches_model<CoeffXyModel>(EstimatorId::kCoeffXyPerTooth));
// An unscented row is its EKF twin's row but for the name, the source and the filter.
constexpr bool twin_matches(const EstimatorInfo& e) {
  const EstimatorInfo& t = estimator_info(e.structure);
  bool keys = true;
  for (std::size_t j = 0; j < e.keys.size(); ++j) {
    keys =
        keys && ((e.keys[j] == nullptr && t.keys[j] == nullptr) ||
                 (e.keys[j] != nullptr && t.keys[j] != nullptr && same_text(e.keys[j], t.keys[j])));
  }
  return t.filter == FilterKind::kExtended && t.structure == t.id && e.states == t.states &&
         e.modal == t.modal && e.measured_axes == t.measured_axes && e.per_tooth == t.per_tooth &&
         e.key_count == t.key_count && keys;
}
static_assert([] {
  for (const EstimatorInfo& e : kEstimators) {
    if (!twin_matches(e)) return false;
  }
  return true;
}());
static_assert(same_text(estimator_info(EstimatorId::kCoeffXy).keys[0], "Kt_N_m2") &&
              same_text(estimator_info(EstimatorId::kCoeffXy).keys[1], "Kr_N_m2"));

template <class Model>
typename Model::Measurement measurement(const MeasuredCut& cut, Eigen::Index k) {
  typename Model::Measurement z;
  z[0] = cut.x_m[k];
  if constexpr (Model::kMeasurements == 2) z[1] = cut.y_m[k];
  return z;
}

// The filter of variant `id` on Model: ToolEkf or ToolUkf.
template <class Model, bool kUnscented>
using FilterOf = std::conditional_t<kUnscented, ToolUkf<Model>, ToolEkf<Model>>;

template <class Filter, class Model>
Filter make_filter(const Model& model, const typename Model::State& x0,
                   const typename Model::StateMatrix& P0, const typename Model::Noise& q,
                   double r_m2, const kalman::UnscentedOptions& ukf) {
  const typename Model::Measurement r = Model::Measurement::Constant(r_m2);
  if constexpr (std::is_same_v<Filter, ToolUkf<Model>>) {
    return make_tool_ukf(model, x0, P0, q, r, ukf);
  } else {
    return make_tool_ekf(model, x0, P0, q, r);
  }
}

// Runs one filter over the cut; `input(chips)` gives the ForceInput of a sample.
template <class Filter, class Model, class InputFn>
EkfResult run_single(EstimatorId id, const MeasuredCut& cut, const CutChips& chips,
                     const Model& model, const typename Model::State& x0,
                     const typename Model::StateMatrix& P0, const typename Model::Noise& q,
                     double r_m2, const kalman::UnscentedOptions& ukf,
                     std::vector<std::string> columns, int history_points, InputFn input) {
  EkfResult res;
  res.id = id;
  res.estimator = estimator_name(id);
  res.time_step_s = cut.time_step_s;
  res.filters = 1;
  const Eigen::Index k0 = chips.first_step();
  const std::int64_t steps = chips.samples() - 1 - k0;
  const double T = cut.time_step_s;
  HistoryRecorder history(columns, steps, history_points);
  Filter filter = make_filter<Filter>(model, x0, P0, q, r_m2, ukf);
  kalman::NisMonitor<Model::kMeasurements> nis;
  history.record(static_cast<double>(k0) * T, filter.state());

  const auto start = std::chrono::steady_clock::now();
  std::int64_t s = 0;
  for (Eigen::Index k = k0; k + 1 < chips.samples(); ++k) {
    filter.predict(input(chips.chips(k)));
    nis.add(filter.update(measurement<Model>(cut, k + 1)));
    ++s;
    if (!filter.state().allFinite()) {
      std::ostringstream m;
      m << "the estimate became non-finite at step " << s << " (t = " << (k + 1) * T << " s)";
      res.summary.fail(m.str());
      break;
    }
    if (history.due(s)) history.record(static_cast<double>(k + 1) * T, filter.state());
  }
  res.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  res.steps = s;
  res.history = history.take();
  res.final_state = filter.state();
  res.covariance_diagonal = filter.covariance().diagonal();
  res.nis = nis.summary();
  res.nis_per_filter = {res.nis};
  for (int i = Model::kFirstParameter; i < Model::kStates; ++i) {
    res.estimates.push_back(
        {columns[static_cast<std::size_t>(i)], filter.state()[i], filter.covariance()(i, i)});
  }
  if (s == steps) res.summary.succeed();
  return res;
}

void validate_modal_inputs(const CutSetup& setup, const ModalEkfInputs& in) {
  require_rule(
      in.coefficients.size() == static_cast<std::size_t>(setup.teeth), "inputs.coefficients.size()",
      in.coefficients.size(),
      "must equal setup.teeth = " + std::to_string(setup.teeth) + " (one Kt, Kr per tooth)");
  require_coefficients(in.coefficients, "inputs.coefficients");
  require_rule(std::isfinite(in.start.m_kg) && in.start.m_kg > 0.0, "inputs.start.m_kg",
               in.start.m_kg, "must be > 0");
  require_rule(std::isfinite(in.start.c_kg_s) && in.start.c_kg_s >= 0.0, "inputs.start.c_kg_s",
               in.start.c_kg_s, "must be >= 0");
  require_rule(std::isfinite(in.start.k_N_m) && in.start.k_N_m > 0.0, "inputs.start.k_N_m",
               in.start.k_N_m, "must be > 0");
}

template <class Model, bool kUnscented>
EkfResult run_modal(EstimatorId id, const MeasuredCut& cut, const CutChips& chips,
                    const ModalEkfInputs& in, const ModalEkfOptions& o) {
  const Model model(cut.time_step_s, o.discretization, in.start);
  typename Model::State x0 = Model::State::Zero();
  typename Model::StateMatrix P0 = Model::StateMatrix::Zero();
  typename Model::Noise q;
  for (int a = 0; a < Model::kAxes; ++a) {
    P0(2 * a, 2 * a) = o.p0_deflection_m2;
    P0(2 * a + 1, 2 * a + 1) = o.p0_velocity_m2_s2;
    q[a] = o.q_force_N2;
  }
  const int w0 = Model::kAxes - Model::kFirstParameter;  // noise index = state index + w0
  if constexpr (Model::kMass >= 0) {
    x0[Model::kMass] = in.start.m_kg;
    P0(Model::kMass, Model::kMass) = o.p0_mass_kg2;
    q[Model::kMass + w0] = o.q_mass;
  }
  if constexpr (Model::kDamping >= 0) {
    x0[Model::kDamping] = in.start.c_kg_s;
    P0(Model::kDamping, Model::kDamping) = o.p0_damping_kg2_s2;
    q[Model::kDamping + w0] = o.q_damping;
  }
  if constexpr (Model::kStiffness >= 0) {
    x0[Model::kStiffness] = in.start.k_N_m;
    P0(Model::kStiffness, Model::kStiffness) = o.p0_stiffness_N2_m2;
    q[Model::kStiffness + w0] = o.q_stiffness;
  }
  if constexpr (kUnscented) {
    // Physically scaled: sd = ukf_p0_relative_sd x the start value (ModalEkfOptions). A start
    // damping of 0 (allowed) would give c no spread and P0 no square root: its scale is then
    // that of 1 % damping, 2 x 0.01 sqrt(k m), with the start (or held) m and k.
    const double c_floor = 0.02 * std::sqrt(in.start.k_N_m * in.start.m_kg);
    for (int i = Model::kFirstParameter; i < Model::kStates; ++i) {
      const double scale = i == Model::kDamping ? std::max(x0[i], c_floor) : x0[i];
      P0(i, i) = std::pow(o.ukf_p0_relative_sd * scale, 2);
    }
  }
  const std::vector<ToothCoefficients>& coefficients = in.coefficients;
  return run_single<FilterOf<Model, kUnscented>>(id, cut, chips, model, x0, P0, q, o.r_m2, o.ukf,
                                                 state_columns(id, 1), o.history_points,
                                                 [&coefficients](const StepChips& c) {
                                                   ForceInput u;
                                                   u.known_N = cutting_force_N(c, coefficients);
                                                   return u;
                                                 });
}

void validate_coeff_inputs(EstimatorId id, const CutSetup& setup, const CoeffEkfInputs& in) {
  const ModalParameters& m = in.modal;
  require_rule(std::isfinite(m.m_kg) && m.m_kg > 0.0, "inputs.modal.m_kg", m.m_kg, "must be > 0");
  require_rule(std::isfinite(m.c_kg_s) && m.c_kg_s >= 0.0, "inputs.modal.c_kg_s", m.c_kg_s,
               "must be >= 0");
  require_rule(std::isfinite(m.k_N_m) && m.k_N_m > 0.0, "inputs.modal.k_N_m", m.k_N_m,
               "must be > 0");
  if (structure_of(id) == EstimatorId::kCoeffXy) {
    require_rule(
        in.start.size() == 1, "inputs.start.size()", in.start.size(),
        std::string("must be 1 for ") + estimator_name(id) + " (one Kt, Kr for every tooth)");
  } else {
    require_rule(
        in.start.size() == static_cast<std::size_t>(setup.teeth), "inputs.start.size()",
        in.start.size(),
        "must equal setup.teeth = " + std::to_string(setup.teeth) + " for " + estimator_name(id));
  }
  require_coefficients(in.start, "inputs.start");
}

CoeffXyModel::StateMatrix coeff_p0(const CoeffEkfOptions& o) {
  CoeffXyModel::StateMatrix P0 = CoeffXyModel::StateMatrix::Zero();
  P0.diagonal() << o.p0_deflection_m2, o.p0_velocity_m2_s2, o.p0_deflection_m2, o.p0_velocity_m2_s2,
      o.p0_Kt, o.p0_Kr;
  return P0;
}

CoeffXyModel::Noise coeff_q(const CoeffEkfOptions& o) {
  CoeffXyModel::Noise q;
  q << o.q_force_N2, o.q_force_N2, o.q_Kt, o.q_Kr;
  return q;
}

template <bool kUnscented>
EkfResult run_coeff_shared(EstimatorId id, const MeasuredCut& cut, const CutChips& chips,
                           const CoeffEkfInputs& in, const CoeffEkfOptions& o) {
  const CoeffXyModel model(cut.time_step_s, o.discretization, in.modal);
  CoeffXyModel::State x0 = CoeffXyModel::State::Zero();
  x0[CoeffXyModel::kKt] = in.start[0].Kt_N_m2;
  x0[CoeffXyModel::kKr] = in.start[0].Kr_N_m2;
  return run_single<FilterOf<CoeffXyModel, kUnscented>>(
      id, cut, chips, model, x0, coeff_p0(o), coeff_q(o), o.r_m2, o.ukf, state_columns(id, 1),
      o.history_points, [](const StepChips& c) {
        ForceInput u;
        for (int p = 0; p < c.teeth; ++p) {
          u.regressor_m2 += tooth_regressor_m2(c.tooth[static_cast<std::size_t>(p)]);
        }
        return u;
      });
}

// The chips of filter p from its own deflection estimates (ekf-coeff-xy-feedback, 000 secs 4.4
// and 8.2): its current estimate p^ = (x^, y^) and its own estimate at t - tau, kept for every
// sample (before the filter starts: the measured deflection). Fills the ForceInput of filter p:
// tooth p's regressor, the other teeth's forces with the other filters' coefficients, and the
// regenerative stiffness dF/dp = sum_q b g_q U(theta_q) K_q (sin theta_q, cos theta_q), with
// U = [[-cos, -sin], [sin, -cos]] (F_q = b w_q U K_q, w_q = h sin + dx sin + dy cos).
// `engaged`: the teeth in the cut (StepChips::engaged), for the per-tooth gate.
template <class Filter>
ForceInput feedback_input(const CutChips& chips, Eigen::Index k, const Eigen::VectorXd& est_x,
                          const Eigen::VectorXd& est_y, const std::vector<Filter>& filters, int p,
                          std::uint32_t* engaged) {
  constexpr int kKt = CoeffXyModel::kKt;
  const MeasuredCut& cut = chips.cut();
  const typename Filter::State& own = filters[static_cast<std::size_t>(p)].state();
  StepMeasurement m;
  m.theta1_rad = cut.theta1_rad[k];
  m.depth_m = cut.depth_m.size() == 1 ? cut.depth_m[0] : cut.depth_m[k];
  m.x_m = own[0];
  m.y_m = own[2];
  m.x_delayed_m = chips.delayed(est_x, k);
  m.y_delayed_m = chips.delayed(est_y, k);
  const StepChips c = chips.model()(m);
  *engaged = c.engaged;
  ForceInput u;
  u.position_m = Eigen::Vector2d(m.x_m, m.y_m);
  for (int q = 0; q < c.teeth; ++q) {
    const ToothChip& t = c.tooth[static_cast<std::size_t>(q)];
    if (!((c.engaged >> q) & 1u)) continue;
    const Eigen::Vector2d K = filters[static_cast<std::size_t>(q)].state().template segment<2>(kKt);
    const Eigen::Matrix2d R = tooth_regressor_m2(t);
    if (q == p) {
      u.regressor_m2 = R;
    } else {
      u.known_N.noalias() += R * K;
    }
    Eigen::Matrix2d unit;
    unit << -t.cos_theta, -t.sin_theta, t.sin_theta, -t.cos_theta;
    const Eigen::Vector2d dF_dw = m.depth_m * (unit * K);
    u.stiffness_N_m.col(0).noalias() += dF_dw * t.sin_theta;
    u.stiffness_N_m.col(1).noalias() += dF_dw * t.cos_theta;
  }
  return u;
}

template <FilterKind kKind>
EkfResult run_coeff_per_tooth(EstimatorId id, const MeasuredCut& cut, const CutChips& chips,
                              const CoeffEkfInputs& in, const CoeffEkfOptions& o) {
  constexpr bool kUnscented = kKind == FilterKind::kUnscented;
  constexpr bool kFeedback = kKind == FilterKind::kExtendedFeedback;
  using Filter = FilterOf<CoeffXyModel, kUnscented>;
  constexpr int kKt = CoeffXyModel::kKt;
  EkfResult res;
  res.id = id;
  res.estimator = estimator_name(res.id);
  res.time_step_s = cut.time_step_s;
  const int n = static_cast<int>(in.start.size());
  res.filters = n;
  const CoeffXyModel model(cut.time_step_s, o.discretization, in.modal);
  const CoeffXyModel::StateMatrix P0 = coeff_p0(o);
  const CoeffXyModel::Noise q = coeff_q(o);
  std::vector<Filter> filters;
  std::vector<kalman::NisMonitor<CoeffXyModel::kMeasurements>> nis(static_cast<std::size_t>(n));
  filters.reserve(static_cast<std::size_t>(n));
  for (const ToothCoefficients& s : in.start) {
    CoeffXyModel::State x0 = CoeffXyModel::State::Zero();
    x0[kKt] = s.Kt_N_m2;
    x0[kKt + 1] = s.Kr_N_m2;
    filters.push_back(make_filter<Filter>(model, x0, P0, q, o.r_m2, o.ukf));
  }
  const kalman::StateMask<CoeffXyModel::kStates> hold = parameter_states<CoeffXyModel>();
  const std::vector<std::string> columns = state_columns(res.id, n);
  const Eigen::Index cols = static_cast<Eigen::Index>(columns.size());
  const auto combined = [&filters, n, cols]() {
    Eigen::VectorXd row(cols);
    row.head<4>() = filters[0].state().template head<4>();
    for (int p = 0; p < n; ++p) {
      row.segment<2>(4 + 2 * p) =
          filters[static_cast<std::size_t>(p)].state().template segment<2>(kKt);
    }
    return row;
  };
  const Eigen::Index k0 = chips.first_step();
  const std::int64_t steps = chips.samples() - 1 - k0;
  const double T = cut.time_step_s;
  HistoryRecorder history(columns, steps, o.history_points);
  history.record(static_cast<double>(k0) * T, combined());
  const bool gated = o.gate == ToothGate::kEngaged;

  std::array<Eigen::Matrix2d, milling::kMaxTeeth> regressor;
  std::array<Eigen::Vector2d, milling::kMaxTeeth> force;
  std::array<ForceInput, milling::kMaxTeeth> inputs;
  // Feedback: each filter's own deflection estimates, one per sample, the measured deflection
  // until the filter has its own (allocated once, before the step loop).
  std::vector<Eigen::VectorXd> est_x, est_y;
  if constexpr (kFeedback) {
    est_x.assign(static_cast<std::size_t>(n), cut.x_m);
    est_y.assign(static_cast<std::size_t>(n), cut.y_m);
  }
  const auto start = std::chrono::steady_clock::now();
  std::int64_t s = 0;
  bool finite = true;
  for (Eigen::Index k = k0; k + 1 < chips.samples() && finite; ++k) {
    std::uint32_t engaged = 0;
    if constexpr (kFeedback) {
      for (int p = 0; p < n; ++p) {
        const std::size_t i = static_cast<std::size_t>(p);
        std::uint32_t teeth_in_cut = 0;
        inputs[i] = feedback_input(chips, k, est_x[i], est_y[i], filters, p, &teeth_in_cut);
        engaged |= teeth_in_cut & (1u << p);  // tooth p in filter p's own chips
      }
    } else {
      const StepChips c = chips.chips(k);
      engaged = c.engaged;
      Eigen::Vector2d total = Eigen::Vector2d::Zero();
      for (int p = 0; p < n; ++p) {
        const std::size_t i = static_cast<std::size_t>(p);
        regressor[i] = tooth_regressor_m2(c.tooth[i]);
        force[i].noalias() = regressor[i] * filters[i].state().template segment<2>(kKt);
        total += force[i];
      }
      for (int p = 0; p < n; ++p) {
        const std::size_t i = static_cast<std::size_t>(p);
        inputs[i].known_N = total - force[i];
        inputs[i].regressor_m2 = regressor[i];
      }
    }
    for (int p = 0; p < n; ++p) {
      const std::size_t i = static_cast<std::size_t>(p);
      filters[i].predict(inputs[i]);
    }
    const CoeffXyModel::Measurement z(cut.x_m[k + 1], cut.y_m[k + 1]);
    for (int p = 0; p < n; ++p) {
      const std::size_t i = static_cast<std::size_t>(p);
      const bool own_tooth_cut = (engaged >> p) & 1u;
      nis[i].add(!gated || own_tooth_cut ? filters[i].update(z)
                                         : filters[i].update_consider(z, hold));
      finite = finite && filters[i].state().allFinite();
      if constexpr (kFeedback) {
        est_x[i][k + 1] = filters[i].state()[0];
        est_y[i][k + 1] = filters[i].state()[2];
      }
    }
    ++s;
    if (!finite) {
      std::ostringstream m;
      m << "the estimate became non-finite at step " << s << " (t = " << (k + 1) * T << " s)";
      res.summary.fail(m.str());
    } else if (history.due(s)) {
      history.record(static_cast<double>(k + 1) * T, combined());
    }
  }
  res.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  res.steps = s;
  res.history = history.take();
  res.final_state = combined();
  res.covariance_diagonal.resize(cols);
  res.covariance_diagonal.head<4>() = filters[0].covariance().diagonal().template head<4>();
  for (int p = 0; p < n; ++p) {
    const Filter& f = filters[static_cast<std::size_t>(p)];
    res.covariance_diagonal.segment<2>(4 + 2 * p) =
        f.covariance().diagonal().template segment<2>(kKt);
    for (int j = 0; j < 2; ++j) {
      res.estimates.push_back({columns[static_cast<std::size_t>(4 + 2 * p + j)], f.state()[kKt + j],
                               f.covariance()(kKt + j, kKt + j)});
    }
  }
  kalman::NisMonitor<CoeffXyModel::kMeasurements> pooled;
  for (const auto& m : nis) {
    pooled.merge(m);
    res.nis_per_filter.push_back(m.summary());
  }
  res.nis = pooled.summary();
  if (s == steps && finite) res.summary.succeed();
  return res;
}

}  // namespace

// The table is in EstimatorId order and its names are unique (its rows match the models: above).
static_assert([] {
  for (std::size_t i = 0; i < kEstimatorCount; ++i) {
    if (static_cast<std::size_t>(kEstimators[i].id) != i) return false;
    for (std::size_t j = 0; j < i; ++j) {
      if (same_text(kEstimators[i].name, kEstimators[j].name)) return false;
    }
  }
  return true;
}());

EstimatorId estimator_from_name(const std::string& name) {
  std::string known;
  for (const EstimatorInfo& e : kEstimators) {
    if (name == e.name) return e.id;
    known += (known.empty() ? "" : ", ") + std::string(e.name);
  }
  throw InputError("estimator = " + name + ": unknown (" + known + ")");
}

std::vector<std::string> estimate_keys(EstimatorId id, int teeth) {
  const EstimatorInfo& e = estimator_info(id);
  std::vector<std::string> keys;
  if (!e.per_tooth) {
    for (int j = 0; j < e.key_count; ++j) keys.emplace_back(e.keys[static_cast<std::size_t>(j)]);
    return keys;
  }
  require_rule(teeth >= 1, "estimate_keys: teeth", teeth, "must be >= 1");
  for (int p = 1; p <= teeth; ++p) {
    for (int j = 0; j < e.key_count; ++j) {
      keys.push_back(e.keys[static_cast<std::size_t>(j)] + std::to_string(p) + "_N_m2");
    }
  }
  return keys;
}

double EkfResult::value(const std::string& key) const {
  for (const Estimate& e : estimates) {
    if (e.key == key) return e.value;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

EkfResult ekf_modal(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                    const ModalEkfInputs& inputs, const ModalEkfOptions& options) {
  require_rule(is_modal(id), "estimator", estimator_name(id), "is not a modal-parameter filter");
  validate(options);
  const CutChips chips(cut, setup);
  validate_modal_inputs(setup, inputs);
  const bool u = is_unscented(id);
  switch (structure_of(id)) {
    case EstimatorId::kModalX:
      return u ? run_modal<ModalXModel, true>(id, cut, chips, inputs, options)
               : run_modal<ModalXModel, false>(id, cut, chips, inputs, options);
    case EstimatorId::kModalXy:
      return u ? run_modal<ModalXyModel, true>(id, cut, chips, inputs, options)
               : run_modal<ModalXyModel, false>(id, cut, chips, inputs, options);
    case EstimatorId::kModalXyMk:
      return u ? run_modal<ModalXyMkModel, true>(id, cut, chips, inputs, options)
               : run_modal<ModalXyMkModel, false>(id, cut, chips, inputs, options);
    default:
      return u ? run_modal<ModalXyMcModel, true>(id, cut, chips, inputs, options)
               : run_modal<ModalXyMcModel, false>(id, cut, chips, inputs, options);
  }
}

EkfResult ekf_coeff(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                    const CoeffEkfInputs& inputs, const CoeffEkfOptions& options) {
  require_rule(!is_modal(id), "estimator", estimator_name(id),
               "is not a cutting-coefficient filter");
  validate(options);
  const CutChips chips(cut, setup);
  validate_coeff_inputs(id, setup, inputs);
  const bool u = is_unscented(id);
  if (structure_of(id) == EstimatorId::kCoeffXy) {
    return u ? run_coeff_shared<true>(id, cut, chips, inputs, options)
             : run_coeff_shared<false>(id, cut, chips, inputs, options);
  }
  switch (estimator_info(id).filter) {
    case FilterKind::kUnscented:
      return run_coeff_per_tooth<FilterKind::kUnscented>(id, cut, chips, inputs, options);
    case FilterKind::kExtendedFeedback:
      return run_coeff_per_tooth<FilterKind::kExtendedFeedback>(id, cut, chips, inputs, options);
    default:
      return run_coeff_per_tooth<FilterKind::kExtended>(id, cut, chips, inputs, options);
  }
}

}  // namespace estimate
}  // namespace chatterlab
