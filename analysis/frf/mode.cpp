#include "analysis/frf/mode.h"

#include <cmath>
#include <complex>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace frf {
namespace {

void require(bool ok, const char* name, double value, const char* rule) {
  if (!ok)
    throw InputError(std::string("mode.") + name + " = " + std::to_string(value) + ": " + rule);
}

}  // namespace

Mode mode_from_mck(double m_kg, double c_kg_s, double k_N_m) {
  require(std::isfinite(m_kg) && m_kg > 0.0, "m_kg", m_kg, "must be > 0");
  require(std::isfinite(c_kg_s) && c_kg_s >= 0.0, "c_kg_s", c_kg_s, "must be >= 0");
  require(std::isfinite(k_N_m) && k_N_m > 0.0, "k_N_m", k_N_m, "must be > 0");
  Mode mode;
  mode.m_kg = m_kg;
  mode.c_kg_s = c_kg_s;
  mode.k_N_m = k_N_m;
  mode.fn_hz = natural_frequency_hz(mode);
  mode.zeta = damping_ratio(mode);
  return mode;
}

Mode mode_from_modal(double fn_hz, double zeta, double m_kg) {
  require(std::isfinite(fn_hz) && fn_hz > 0.0, "fn_hz", fn_hz, "must be > 0");
  require(std::isfinite(zeta) && zeta >= 0.0, "zeta", zeta, "must be >= 0");
  require(std::isfinite(m_kg) && m_kg > 0.0, "m_kg", m_kg, "must be > 0");
  const double wn = kTwoPi * fn_hz;
  Mode mode;
  mode.fn_hz = fn_hz;
  mode.zeta = zeta;
  mode.m_kg = m_kg;
  mode.k_N_m = m_kg * wn * wn;
  mode.c_kg_s = 2.0 * zeta * std::sqrt(mode.k_N_m * m_kg);
  return mode;
}

std::optional<Mode> dominant_mode(const std::vector<Mode>& modes) {
  const auto peak = [](const Mode& m) { return 1.0 / (m.c_kg_s * kTwoPi * m.fn_hz); };
  const Mode* best = nullptr;
  for (const Mode& m : modes) {
    if (!best || peak(m) > peak(*best)) best = &m;
  }
  if (!best) return std::nullopt;
  return *best;
}

Eigen::VectorXcd receptance(const std::vector<Mode>& modes,
                            const Eigen::Ref<const Eigen::VectorXd>& f_hz) {
  Eigen::VectorXcd h = Eigen::VectorXcd::Zero(f_hz.size());
  for (const Mode& mode : modes) {
    const double wn = kTwoPi * mode.fn_hz;
    for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
      const double w = kTwoPi * f_hz[i];
      // 003 eq. 4-27, A = 1/m.
      h[i] += (1.0 / mode.m_kg) / std::complex<double>(wn * wn - w * w, 2.0 * mode.zeta * wn * w);
    }
  }
  return h;
}

}  // namespace frf
}  // namespace chatterlab
