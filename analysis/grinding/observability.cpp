#include "analysis/grinding/observability.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace grinding {

namespace {

// Uniform in [0, 1) from the top 53 bits (platform-independent).
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

[[noreturn]] void fail(const std::string& what) {
  throw InputError("grinding observability: " + what);
}

}  // namespace

GrindingObservability grinding_observability(const ProcessState& X, double u_mm_s,
                                             const GrindingParameters& p, int states,
                                             const GrindingChannels& channels,
                                             const GrindingObservabilityOptions& o) {
  if (states != 3 && states != 4) fail("states must be 3 or 4");
  const std::array<bool, 4> use{channels.power, channels.Dw, channels.ds, channels.Ra};
  const int m = static_cast<int>(std::count(use.begin(), use.end(), true));
  if (m == 0) fail("no channel");
  if (!X.allFinite() || !std::isfinite(u_mm_s)) fail("non-finite operating point");
  if (!(p.tau_s > 0.0)) fail("tau_s must be > 0");
  if (!(o.relative_tolerance > 0.0)) fail("relative_tolerance must be > 0");
  if (!((o.state_scale.array() > 0.0).all() && (o.output_scale.array() > 0.0).all()))
    fail("scales must be > 0");

  // Continuous Jacobians dF/dX (002 eqs 1-3, 6) and dH/dX (appendix A, eq. 11).
  Eigen::Matrix4d J, H;
  process_derivative(X, u_mm_s, p, &J);
  outputs(X, p, &H);

  const int n = states;
  const Eigen::VectorXd sx = o.state_scale.head(n);
  Eigen::MatrixXd A =
      p.tau_s * (sx.cwiseInverse().asDiagonal() * J.topLeftCorner(n, n) * sx.asDiagonal());
  Eigen::MatrixXd C(m, n);
  for (int c = 0, r = 0; c < 4; ++c) {
    if (!use[static_cast<std::size_t>(c)]) continue;
    C.row(r++) = H.row(c).head(n).cwiseProduct(sx.transpose()) / o.output_scale[c];
  }
  Eigen::MatrixXd O(m * n, n);
  Eigen::MatrixXd CAk = C;
  for (int k = 0; k < n; ++k) {
    O.middleRows(k * m, m) = CAk;
    CAk = CAk * A;
  }

  GrindingObservability res;
  res.states = n;
  res.relative_tolerance = o.relative_tolerance;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(O);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double largest = sv.size() > 0 ? sv[0] : 0.0;
  res.singular_values = largest > 0.0 ? Eigen::VectorXd(sv / largest) : Eigen::VectorXd(sv);
  res.rank = 0;
  if (largest > 0.0)
    for (Eigen::Index i = 0; i < sv.size(); ++i)
      if (sv[i] > o.relative_tolerance * largest) ++res.rank;
  return res;
}

TrajectoryObservability observability_along_trajectory(const Eigen::MatrixX4d& trajectory,
                                                       const Eigen::VectorXd& u_mm_s,
                                                       const GrindingParameters& p, int states,
                                                       const GrindingChannels& channels, int points,
                                                       std::uint64_t seed,
                                                       const GrindingObservabilityOptions& o) {
  if (trajectory.rows() != u_mm_s.size()) fail("trajectory and u_mm_s differ in length");
  if (points < 1) fail("points must be >= 1");
  std::vector<Eigen::Index> eligible;
  for (Eigen::Index r = 0; r < trajectory.rows(); ++r)
    if (trajectory(r, kV) > o.min_v_mm_s && trajectory(r, kVw) > 0.0) eligible.push_back(r);
  if (eligible.empty()) fail("no trajectory row has x2 above min_v_mm_s and x1 > 0");

  // Partial Fisher-Yates: the first `count` entries become a uniform draw without replacement.
  std::mt19937_64 rng(seed);
  const std::size_t count = std::min(eligible.size(), static_cast<std::size_t>(points));
  for (std::size_t a = 0; a < count; ++a) {
    const std::size_t left = eligible.size() - a;
    const std::size_t b =
        a +
        std::min(left - 1, static_cast<std::size_t>(uniform01(rng) * static_cast<double>(left)));
    std::swap(eligible[a], eligible[b]);
  }
  eligible.resize(count);
  std::sort(eligible.begin(), eligible.end());

  TrajectoryObservability out;
  out.min_rank = states;
  out.max_rank = 0;
  out.smallest_kept = 1.0;
  out.largest_dropped = 0.0;
  for (Eigen::Index r : eligible) {
    const ProcessState X = trajectory.row(r).transpose();
    ObservabilityPoint pt;
    pt.row = r;
    pt.result = grinding_observability(X, u_mm_s[r], p, states, channels, o);
    const GrindingObservability& g = pt.result;
    out.min_rank = std::min(out.min_rank, g.rank);
    out.max_rank = std::max(out.max_rank, g.rank);
    if (g.rank > 0) out.smallest_kept = std::min(out.smallest_kept, g.singular_values[g.rank - 1]);
    if (g.rank < g.singular_values.size())
      out.largest_dropped = std::max(out.largest_dropped, g.singular_values[g.rank]);
    out.points.push_back(std::move(pt));
  }
  return out;
}

std::array<ObservabilityCase, 4> table_i_cases() {
  return {{
      {"case 1: P, D_w", 3, {true, true, false, false}},
      {"case 1: P + (d_s)", 3, {true, false, true, false}},
      {"case 2: P, D_w + (d_s)", 4, {true, true, true, false}},
      {"case 2: P + (d_s, R_a)", 4, {true, false, true, true}},
  }};
}

ObservabilityCase estimator_observability_case(GrindingEstimatorId id) {
  for (const GrindingEstimatorInfo& e : kGrindingEstimators) {
    if (e.id != id) continue;
    return {e.name, e.estimates_R0 ? 4 : 3, {true, true, e.uses_ds, e.uses_Ra}};
  }
  fail("unknown estimator id");
}

}  // namespace grinding
}  // namespace chatterlab
