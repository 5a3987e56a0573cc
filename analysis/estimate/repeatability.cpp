#include "analysis/estimate/repeatability.h"

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

namespace chatterlab {
namespace estimate {

namespace {

void validate(const RepeatabilityOptions& o) {
  const auto fail = [](const char* field, double v, const char* rule) {
    std::ostringstream m;
    m << "repeat." << field << " = " << v << ": " << rule;
    throw InputError(m.str());
  };
  if (o.runs < 2) fail("runs", o.runs, "must be >= 2");
  if (!(o.spread >= 0.0 && o.spread < 1.0)) fail("spread", o.spread, "must be in [0, 1)");
}

// Uniform in [0, 1) from the top 53 bits (platform-independent, unlike
// std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

// `run(draw)` runs one trial, drawing each estimated parameter's start with draw(reference).
RepeatabilityResult repeat(
    const RepeatabilityOptions& o,
    const std::function<EkfResult(const std::function<double(double)>&)>& run) {
  validate(o);
  RepeatabilityResult res;
  std::mt19937_64 rng(o.seed);
  std::vector<double> drawn;
  const std::function<double(double)> draw = [&](double reference) {
    const double v = reference * (1.0 + o.spread * (2.0 * uniform01(rng) - 1.0));
    drawn.push_back(v);
    return v;
  };
  for (int r = 0; r < o.runs; ++r) {
    drawn.clear();
    EkfResult e = run(draw);
    if (r == 0) {
      for (const Estimate& est : e.estimates) res.keys.push_back(est.key);
      const Eigen::Index k = static_cast<Eigen::Index>(res.keys.size());
      res.initial.setConstant(o.runs, k, std::numeric_limits<double>::quiet_NaN());
      res.finals.setConstant(o.runs, k, std::numeric_limits<double>::quiet_NaN());
    }
    for (std::size_t j = 0; j < drawn.size() && j < res.keys.size(); ++j) {
      res.initial(r, static_cast<Eigen::Index>(j)) = drawn[j];
    }
    if (e.summary.ok()) {
      for (std::size_t j = 0; j < e.estimates.size(); ++j) {
        res.finals(r, static_cast<Eigen::Index>(j)) = e.estimates[j].value;
      }
    } else if (!res.summary.ran()) {
      res.summary.fail("run " + std::to_string(r + 1) + " of " + std::to_string(o.runs) + ": " +
                       e.summary.message);
    }
    res.runs.push_back(std::move(e));
  }
  const Eigen::Index k = res.finals.cols();
  res.mean.setConstant(k, std::numeric_limits<double>::quiet_NaN());
  res.std_dev = res.mean;
  res.min = res.mean;
  res.max = res.mean;
  res.range = res.mean;
  for (Eigen::Index j = 0; j < k; ++j) {
    std::vector<double> v;
    for (Eigen::Index r = 0; r < res.finals.rows(); ++r) {
      if (std::isfinite(res.finals(r, j))) v.push_back(res.finals(r, j));
    }
    if (v.empty()) continue;
    const Eigen::Map<const Eigen::VectorXd> x(v.data(), static_cast<Eigen::Index>(v.size()));
    res.mean[j] = x.mean();
    res.min[j] = x.minCoeff();
    res.max[j] = x.maxCoeff();
    res.range[j] = res.max[j] - res.min[j];
    res.std_dev[j] = v.size() > 1 ? std::sqrt((x.array() - res.mean[j]).square().sum() /
                                              static_cast<double>(v.size() - 1))
                                  : 0.0;
  }
  if (!res.summary.ran()) res.summary.succeed();
  return res;
}

}  // namespace

RepeatabilityResult repeat_modal(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                                 const ModalEkfInputs& reference, const ModalEkfOptions& options,
                                 const RepeatabilityOptions& o) {
  return repeat(o, [&](const std::function<double(double)>& draw) {
    ModalEkfInputs in = reference;
    // Draw order = estimate-key order (m, c, k).
    in.start.m_kg = draw(reference.start.m_kg);
    if (structure_of(id) != EstimatorId::kModalXyMk) in.start.c_kg_s = draw(reference.start.c_kg_s);
    if (structure_of(id) != EstimatorId::kModalXyMc) in.start.k_N_m = draw(reference.start.k_N_m);
    return ekf_modal(id, cut, setup, in, options);
  });
}

RepeatabilityResult repeat_coeff(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                                 const CoeffEkfInputs& reference, const CoeffEkfOptions& options,
                                 const RepeatabilityOptions& o) {
  return repeat(o, [&](const std::function<double(double)>& draw) {
    CoeffEkfInputs in = reference;
    for (std::size_t p = 0; p < in.start.size(); ++p) {
      in.start[p].Kt_N_m2 = draw(reference.start[p].Kt_N_m2);
      in.start[p].Kr_N_m2 = draw(reference.start[p].Kr_N_m2);
    }
    return ekf_coeff(id, cut, setup, in, options);
  });
}

}  // namespace estimate
}  // namespace chatterlab
