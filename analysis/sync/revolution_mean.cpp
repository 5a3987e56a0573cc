#include "analysis/sync/revolution_mean.h"

#include <cmath>
#include <sstream>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace sync {

namespace {

void require_tach(const TachAngle& tach, const char* who) {
  if (!tach.summary.ok()) {
    throw InputError(std::string(who) + ": the tachometer step did not succeed (" +
                     tach.summary.message + ")");
  }
}

// Linear interpolation of x at fractional sample position p, 0 <= p <= x.size() - 1.
double at_position(const Eigen::Ref<const Eigen::VectorXd>& x, double p) {
  const auto i = static_cast<Eigen::Index>(std::floor(p));
  if (i >= x.size() - 1) return x[x.size() - 1];
  const double f = p - static_cast<double>(i);
  return (1.0 - f) * x[i] + f * x[i + 1];
}

}  // namespace

RevolutionRange whole_revolutions_in(const TachAngle& tach, double start_s, double end_s) {
  require_tach(tach, "whole_revolutions_in");
  const double a = start_s * tach.fs_hz;
  const double b = end_s * tach.fs_hz;
  // A relative slack of 1e-9 sample keeps an edge exactly on the window boundary inside.
  const double slack = 1e-9 * std::max(1.0, std::abs(b));
  RevolutionRange r;
  r.first = -1;
  for (int k = 0; k < tach.revolutions; ++k) {
    const double e0 = tach.edges[static_cast<std::size_t>(k)];
    const double e1 = tach.edges[static_cast<std::size_t>(k) + 1];
    if (e0 >= a - slack && e1 <= b + slack) {
      if (r.first < 0) r.first = k;
      ++r.count;
    }
  }
  if (r.first < 0) r.first = 0;
  return r;
}

RevolutionMean mean_revolution(const Eigen::Ref<const Eigen::VectorXd>& x_m,
                               const Eigen::Ref<const Eigen::VectorXd>& y_m, const TachAngle& tach,
                               RevolutionRange range, int phase_points) {
  require_tach(tach, "mean_revolution");
  if (x_m.size() != tach.phase_rad.size() || y_m.size() != tach.phase_rad.size()) {
    std::ostringstream m;
    m << "mean_revolution: x has " << x_m.size() << " samples, y " << y_m.size()
      << ", the tachometer record " << tach.phase_rad.size() << ": must be equal";
    throw InputError(m.str());
  }
  if (phase_points < 8) {
    throw InputError("mean_revolution: phase_points = " + std::to_string(phase_points) +
                     ": must be >= 8");
  }
  if (range.count < 1 || range.first < 0 || range.first + range.count > tach.revolutions) {
    std::ostringstream m;
    m << "mean_revolution: revolutions " << range.first << " .. " << range.first + range.count - 1
      << ": must be a non-empty range within 0 .. " << tach.revolutions - 1;
    throw InputError(m.str());
  }
  const int N = phase_points;
  RevolutionMean out;
  out.revolutions = range;
  out.phase_rad.resize(N);
  for (int j = 0; j < N; ++j) out.phase_rad[j] = kTwoPi * j / N;
  // Running sums of the resampled revolutions and of their squares (Welford per point).
  Eigen::VectorXd mx = Eigen::VectorXd::Zero(N), my = Eigen::VectorXd::Zero(N);
  Eigen::VectorXd sx = Eigen::VectorXd::Zero(N), sy = Eigen::VectorXd::Zero(N);
  for (int c = 0; c < range.count; ++c) {
    const auto k = static_cast<std::size_t>(range.first + c);
    const double e0 = tach.edges[k];
    const double len = tach.edges[k + 1] - e0;
    for (int j = 0; j < N; ++j) {
      const double p = e0 + len * j / N;
      const double vx = at_position(x_m, p);
      const double vy = at_position(y_m, p);
      const double dx = vx - mx[j];
      const double dy = vy - my[j];
      mx[j] += dx / (c + 1);
      my[j] += dy / (c + 1);
      sx[j] += dx * (vx - mx[j]);
      sy[j] += dy * (vy - my[j]);
    }
  }
  out.x_m = mx;
  out.y_m = my;
  if (range.count > 1) {
    out.std_x_m = (sx / (range.count - 1)).cwiseSqrt();
    out.std_y_m = (sy / (range.count - 1)).cwiseSqrt();
  } else {
    out.std_x_m = Eigen::VectorXd::Constant(N, std::numeric_limits<double>::quiet_NaN());
    out.std_y_m = out.std_x_m;
  }
  out.start_s = tach.edges[static_cast<std::size_t>(range.first)] / tach.fs_hz;
  out.end_s = tach.edges[static_cast<std::size_t>(range.first + range.count)] / tach.fs_hz;
  return out;
}

double periodic_interpolate(const Eigen::Ref<const Eigen::VectorXd>& values, double phase_rad) {
  const Eigen::Index n = values.size();
  double u = std::fmod(phase_rad, kTwoPi) / kTwoPi * static_cast<double>(n);
  if (u < 0.0) u += static_cast<double>(n);
  auto j = static_cast<Eigen::Index>(u);
  const double f = u - static_cast<double>(j);
  if (j >= n) j -= n;  // u rounded up to n
  const Eigen::Index j1 = j + 1 == n ? 0 : j + 1;
  return (1.0 - f) * values[j] + f * values[j1];
}

}  // namespace sync
}  // namespace chatterlab
