#include "analysis/sifs/calibration.h"

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "analysis/common/require.h"

namespace chatterlab {
namespace sifs {

namespace {

// The loads span an axis when the group's load matrix F (3 x windows) has a singular value
// above this fraction of its largest: loads are set to a few decimals, so a dependent
// direction shows as rounding only.
constexpr double kLoadRankTolerance = 1e-9;
// S is taken as singular above this 2-norm condition number: C = S^-1 would keep fewer than
// ~4 significant digits (condition number times machine epsilon above 1e-4).
constexpr double kMaxConditionS = 1e12;

// The sample indices of a window: start_s <= k / fs <= end_s, a window edge on a sample
// (to rounding of start_s fs) included.
struct SampleRange {
  Eigen::Index first = 0;
  Eigen::Index last = -1;  // inclusive
  Eigen::Index count() const { return last - first + 1; }
};
SampleRange window_samples(const LoadWindow& w, double fs_hz, Eigen::Index n) {
  constexpr double kEdge = 1e-9;  // of a sample
  SampleRange r;
  r.first =
      std::max<Eigen::Index>(0, static_cast<Eigen::Index>(std::ceil(w.start_s * fs_hz - kEdge)));
  r.last =
      std::min<Eigen::Index>(n - 1, static_cast<Eigen::Index>(std::floor(w.end_s * fs_hz + kEdge)));
  return r;
}

std::string window_text(const LoadWindow& w) {
  std::ostringstream m;
  m << "window [" << w.start_s << ", " << w.end_s << "] s";
  return m.str();
}

[[noreturn]] void window_error(std::size_t i, const LoadWindow& w, const std::string& rule) {
  throw InputError("loads[" + std::to_string(i) + "]: " + window_text(w) + " " + rule);
}

bool overlaps(const LoadWindow& a, const LoadWindow& b) {
  return a.start_s < b.end_s && b.start_s < a.end_s;
}

}  // namespace

const char* to_string(Axis a) {
  switch (a) {
    case Axis::kX:
      return "x";
    case Axis::kY:
      return "y";
    case Axis::kZ:
      return "z";
  }
  return "?";
}

Pairs pair_signals(const Washers& w) {
  Pairs p(w.rows(), 3);
  // 003 eq. 3-1 with the Z pair summed (notes/003.md decision 1).
  p.col(0) = 0.5 * (w.col(0) - w.col(1));
  p.col(1) = -0.5 * (w.col(2) - w.col(3));
  p.col(2) = 0.5 * (w.col(4) + w.col(5));
  return p;
}

StaticReduction reduce_static_test(const Washers& w, double fs_hz, Axis axis,
                                   const std::vector<LoadWindow>& windows) {
  require_rule(std::isfinite(fs_hz) && fs_hz > 0.0, "sample_rate_hz", fs_hz,
               "must be finite and > 0");
  if (windows.empty()) throw InputError("loads: no window");
  const Eigen::Index n = w.rows();
  const double duration_s = static_cast<double>(n) / fs_hz;

  std::vector<SampleRange> ranges(windows.size());
  for (std::size_t i = 0; i < windows.size(); ++i) {
    const LoadWindow& lw = windows[i];
    if (!(std::isfinite(lw.start_s) && std::isfinite(lw.end_s) && std::isfinite(lw.load_n))) {
      std::ostringstream m;
      m << "loads[" << i << "] = [" << lw.start_s << ", " << lw.end_s << ", " << lw.load_n
        << "]: must be finite";
      throw InputError(m.str());
    }
    if (lw.start_s < 0.0) window_error(i, lw, "starts before the record (0 s)");
    if (!(lw.end_s > lw.start_s)) window_error(i, lw, "does not end after its start");
    if (lw.end_s > duration_s) {
      std::ostringstream m;
      m << "ends after the record (" << duration_s << " s)";
      window_error(i, lw, m.str());
    }
    ranges[i] = window_samples(lw, fs_hz, n);
    if (ranges[i].count() < 2) window_error(i, lw, "holds fewer than 2 samples");
    for (std::size_t j = 0; j < i; ++j)
      if (overlaps(windows[j], lw))
        window_error(i, lw,
                     "overlaps loads[" + std::to_string(j) + "] (" + window_text(windows[j]) + ")");
  }

  // Format sec. 6 "sifs-static": an unloaded window before the first load and one after the
  // last, so the drift line is pinned on both sides of the loading.
  double first_load_s = std::numeric_limits<double>::infinity();
  double last_load_s = -std::numeric_limits<double>::infinity();
  for (const LoadWindow& lw : windows)
    if (lw.load_n != 0.0) {
      first_load_s = std::min(first_load_s, lw.start_s);
      last_load_s = std::max(last_load_s, lw.end_s);
    }
  if (!std::isfinite(first_load_s)) throw InputError("loads: no loaded window (every load is 0)");
  bool before = false, after = false;
  for (const LoadWindow& lw : windows)
    if (lw.load_n == 0.0) {
      before = before || lw.end_s <= first_load_s;
      after = after || lw.start_s >= last_load_s;
    }
  if (!before) throw InputError("loads: no unloaded window before the first load");
  if (!after) throw InputError("loads: no unloaded window after the last load");

  for (std::size_t i = 0; i < windows.size(); ++i)
    for (Eigen::Index k = ranges[i].first; k <= ranges[i].last; ++k)
      if (!w.row(k).allFinite()) {
        std::ostringstream m;
        m << "data row " << k << " (t = " << static_cast<double>(k) / fs_hz << " s, inside loads["
          << i << "]): non-finite washer value";
        throw InputError(m.str());
      }

  StaticReduction red;
  red.axis = axis;
  red.windows = windows;

  // Drift (notes/003.md decision 7): per channel a + b t by least squares over every sample of
  // the unloaded windows, t = k / fs. Centred on the mean time for a well-conditioned solve.
  double count = 0.0, sum_t = 0.0;
  for (std::size_t i = 0; i < windows.size(); ++i)
    if (windows[i].load_n == 0.0)
      for (Eigen::Index k = ranges[i].first; k <= ranges[i].last; ++k) {
        count += 1.0;
        sum_t += static_cast<double>(k) / fs_hz;
      }
  const double t_mean = sum_t / count;
  double s_tt = 0.0;
  Eigen::Matrix<double, 6, 1> sum_x = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> s_tx = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t i = 0; i < windows.size(); ++i)
    if (windows[i].load_n == 0.0)
      for (Eigen::Index k = ranges[i].first; k <= ranges[i].last; ++k) {
        const double dt = static_cast<double>(k) / fs_hz - t_mean;
        s_tt += dt * dt;
        sum_x += w.row(k).transpose();
        s_tx += dt * w.row(k).transpose();
      }
  red.drift_per_s = s_tx / s_tt;
  red.drift_offset = sum_x / count - red.drift_per_s * t_mean;

  // Per window: the mean washer values minus the drift line at the window's mean time (the
  // mean of a + b t), then the pairs of 003 eq. 3-1 (linear, so pairing the means is exact).
  for (std::size_t i = 0; i < windows.size(); ++i) {
    const SampleRange& r = ranges[i];
    const double samples = static_cast<double>(r.count());
    const Eigen::Matrix<double, 6, 1> mean_w =
        w.middleRows(r.first, r.count()).colwise().sum().transpose() / samples;
    const double mean_t = 0.5 * static_cast<double>(r.first + r.last) / fs_hz;
    const Eigen::Matrix<double, 6, 1> corrected =
        mean_w - red.drift_offset - red.drift_per_s * mean_t;
    Washers one(1, 6);
    one.row(0) = corrected.transpose();
    red.s.push_back(pair_signals(one).row(0).transpose());
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    f[static_cast<int>(axis)] = windows[i].load_n;
    red.f.push_back(f);
  }
  red.summary.succeed();
  return red;
}

CalibrationFit fit_calibration(const std::vector<StaticReduction>& tests) {
  CalibrationFit fit;
  fit.linearity_pct.setConstant(std::numeric_limits<double>::quiet_NaN());
  std::size_t total = 0;
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const StaticReduction& t = tests[i];
    if (!t.summary.ok())
      throw InputError("tests[" + std::to_string(i) + "]: the static reduction did not succeed (" +
                       t.summary.message + ")");
    if (t.s.size() != t.f.size() || t.s.size() != t.windows.size())
      throw InputError("tests[" + std::to_string(i) + "]: s, f and windows differ in length");
    total += t.s.size();
  }
  fit.windows = static_cast<int>(total);
  if (total == 0) {
    fit.summary.fail("no load window in the group");
    return fit;
  }

  const auto W = static_cast<Eigen::Index>(total);
  Eigen::MatrixXd F(W, 3), Sm(W, 3);  // rows f_w^T and s_w^T
  Eigen::Index row = 0;
  for (const StaticReduction& t : tests)
    for (std::size_t j = 0; j < t.s.size(); ++j, ++row) {
      F.row(row) = t.f[j].transpose();
      Sm.row(row) = t.s[j].transpose();
    }

  // The group must load three independent axes (format sec. 6 "Group").
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd_f(F);
  const Eigen::Vector3d sv_f = svd_f.singularValues();
  int rank = 0;
  for (int i = 0; i < 3; ++i)
    if (sv_f[i] > kLoadRankTolerance * sv_f[0]) ++rank;
  if (rank < 3) {
    std::ostringstream m;
    m << "the loads span " << rank << (rank == 1 ? " independent axis" : " independent axes")
      << " (loaded:";
    for (int a = 0; a < 3; ++a)
      if (F.col(a).cwiseAbs().maxCoeff() > 0.0) m << " " << to_string(static_cast<Axis>(a));
    m << "); the calibration needs loads along x, y and z";
    fit.summary.fail(m.str());
    return fit;
  }

  // s_w = S f_w for every window, no intercept: F S^T = Sm in the least-squares sense.
  fit.S = F.colPivHouseholderQr().solve(Sm).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd_s(fit.S);
  const Eigen::Vector3d sv_s = svd_s.singularValues();
  fit.cond_S = sv_s[2] > 0.0 ? sv_s[0] / sv_s[2] : std::numeric_limits<double>::infinity();
  if (!(fit.cond_S < kMaxConditionS)) {
    std::ostringstream m;
    m << "S is singular (2-norm condition number " << fit.cond_S << ")";
    fit.summary.fail(m.str());
    return fit;
  }
  fit.C = fit.S.inverse();

  // Residuals C s_w - f_w over the loaded windows.
  double sum_sq = 0.0, max_abs = 0.0, max_load = 0.0;
  for (const StaticReduction& t : tests)
    for (std::size_t j = 0; j < t.s.size(); ++j) {
      if (t.windows[j].load_n == 0.0) continue;
      const Eigen::Vector3d r = fit.C * t.s[j] - t.f[j];
      fit.residuals_n.push_back(r);
      sum_sq += r.squaredNorm();
      max_abs = std::max(max_abs, r.cwiseAbs().maxCoeff());
      max_load = std::max(max_load, std::abs(t.windows[j].load_n));
    }
  fit.residual_rms_n = std::sqrt(sum_sq / (3.0 * static_cast<double>(fit.residuals_n.size())));
  fit.residual_max_pct = 100.0 * max_abs / max_load;

  // Linearity per axis: s_a = p + q load by least squares over the windows of that axis's
  // tests; the largest deviation in % of the largest |s_a| (% FSO, 003 table 1).
  for (int a = 0; a < 3; ++a) {
    double m = 0.0, sl = 0.0, ss = 0.0;
    for (const StaticReduction& t : tests)
      if (static_cast<int>(t.axis) == a)
        for (std::size_t j = 0; j < t.s.size(); ++j) {
          m += 1.0;
          sl += t.windows[j].load_n;
          ss += t.s[j][a];
        }
    if (m == 0.0) continue;
    const double l_mean = sl / m, s_mean = ss / m;
    double s_ll = 0.0, s_ls = 0.0;
    for (const StaticReduction& t : tests)
      if (static_cast<int>(t.axis) == a)
        for (std::size_t j = 0; j < t.s.size(); ++j) {
          const double dl = t.windows[j].load_n - l_mean;
          s_ll += dl * dl;
          s_ls += dl * (t.s[j][a] - s_mean);
        }
    if (!(s_ll > 0.0)) continue;  // every window at one load: no line
    const double slope = s_ls / s_ll;
    double dev = 0.0, full_scale = 0.0;
    for (const StaticReduction& t : tests)
      if (static_cast<int>(t.axis) == a)
        for (std::size_t j = 0; j < t.s.size(); ++j) {
          const double line = s_mean + slope * (t.windows[j].load_n - l_mean);
          dev = std::max(dev, std::abs(t.s[j][a] - line));
          full_scale = std::max(full_scale, std::abs(t.s[j][a]));
        }
    if (full_scale > 0.0) fit.linearity_pct[a] = 100.0 * dev / full_scale;
  }
  fit.summary.succeed();
  return fit;
}

}  // namespace sifs
}  // namespace chatterlab
