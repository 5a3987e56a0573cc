#include "analysis/sysid/era_validation.h"

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "analysis/common/require.h"
#include "analysis/common/stopwatch.h"
#include "analysis/signal/fft.h"

namespace chatterlab {
namespace sysid {
namespace {

using Clock = SteadyClock;

// splitmix64 (Steele, Lea and Flood 2014): a fixed mixing of the seed, the same on every
// standard library (std::uniform_int_distribution is not).
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double median_of(std::vector<double> v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : percentile_linear(std::move(v), 50);
}

FitStatistics statistics(const std::vector<const EraValidationRow*>& rows, bool era) {
  FitStatistics s;
  std::vector<double> fits, orders, times;
  for (const EraValidationRow* r : rows) {
    const bool ok = era ? r->era_ok : r->subspace_ok;
    const double fit = era ? r->era_fit_pct : r->subspace_fit_pct;
    ++s.count;
    times.push_back(era ? r->era_runtime_s : r->subspace_runtime_s);
    if (!ok || !std::isfinite(fit)) {
      ++s.failures;
      fits.push_back(-std::numeric_limits<double>::infinity());
      continue;
    }
    fits.push_back(fit);
    orders.push_back(era ? r->era_order : r->subspace_order);
  }
  if (fits.empty()) return s;
  s.median = percentile_linear(fits, 50.0);
  s.p10 = percentile_linear(fits, 10.0);
  s.min = *std::min_element(fits.begin(), fits.end());
  s.max = *std::max_element(fits.begin(), fits.end());
  s.median_order = median_of(orders);
  s.median_runtime_s = median_of(times);
  return s;
}

}  // namespace

double percentile_linear(std::vector<double> v, double p) {
  require_rule(!v.empty(), "sample", "empty", "needs at least one value");
  require_rule(p >= 0.0 && p <= 100.0, "percentile", p, "must be in [0, 100]");
  std::sort(v.begin(), v.end());
  const double h = static_cast<double>(v.size() - 1) * p / 100.0;
  const std::size_t j = static_cast<std::size_t>(std::floor(h));
  if (j + 1 >= v.size()) return v.back();
  const double t = h - static_cast<double>(j);
  if (t == 0.0 || v[j + 1] == v[j]) return v[j];
  // An infinite neighbour (a failure, -inf) makes the interpolation infinite; the formula
  // would give -inf + inf = NaN.
  if (std::isinf(v[j])) return v[j];
  if (std::isinf(v[j + 1])) return v[j + 1];
  return v[j] + t * (v[j + 1] - v[j]);
}

EraValidationStudy run_era_validation(const EraValidationOptions& o) {
  require_rule(!o.snr_db.empty(), "snr_db", "empty", "needs at least one level");
  for (double snr : o.snr_db) {
    require_rule(std::isfinite(snr) || snr == std::numeric_limits<double>::infinity(), "snr_db",
                 snr, "must be finite or +inf (noise-free)");
  }
  require_rule(o.systems_per_level >= 1, "systems_per_level", o.systems_per_level, "must be >= 1");
  require_rule(o.min_order >= 1 && o.min_order <= o.max_order, "order range",
               std::to_string(o.min_order) + " .. " + std::to_string(o.max_order),
               "must satisfy 1 <= min_order <= max_order");
  require_rule(o.record_length >= 16 && o.record_length % 2 == 0, "record_length", o.record_length,
               "must be even and >= 16");
  require_rule(std::isfinite(o.sample_rate_hz) && o.sample_rate_hz > 0.0, "sample_rate_hz",
               o.sample_rate_hz, "must be finite and > 0");
  const auto t0 = Clock::now();
  const int N = o.record_length;
  const Eigen::Index M = N / 2;
  const double rate = o.sample_rate_hz;
  EraValidationStudy study;
  study.record_length = N;
  Eigen::VectorXd f(M + 1);
  for (Eigen::Index m = 0; m <= M; ++m) f[m] = static_cast<double>(m) * rate / N;
  const Eigen::VectorXd f_fit = f.tail(M);  // 0 < f <= rate/2
  signal::RealFft fft(N);

  // Steps 1-2 once per system (the same systems at every level).
  struct System {
    std::uint64_t seed;
    DiscreteStateSpace truth;
    Eigen::VectorXd y;
    Eigen::VectorXcd G_fit;
    double mean_square;
  };
  std::vector<System> systems;
  std::vector<double> true_orders;
  const int span = o.max_order - o.min_order + 1;
  for (int i = 0; i < o.systems_per_level; ++i) {
    System s;
    s.seed = o.seed + static_cast<std::uint64_t>(i);
    RandomSystemOptions so = o.system;
    so.order =
        o.min_order + static_cast<int>(splitmix64(s.seed) % static_cast<std::uint64_t>(span));
    s.truth = random_stable_system(so, rate, s.seed);
    s.y.resize(N);
    s.y[0] = s.truth.D;
    Eigen::VectorXd x = s.truth.B;
    for (int k = 1; k < N; ++k) {
      s.y[k] = s.truth.C.dot(x);
      x = s.truth.A * x;
    }
    s.mean_square = s.y.squaredNorm() / N;
    s.G_fit = frequency_response(s.truth, f_fit);
    true_orders.push_back(so.order);
    systems.push_back(std::move(s));
  }
  study.median_true_order = median_of(true_orders);

  for (std::size_t level = 0; level < o.snr_db.size(); ++level) {
    const double snr = o.snr_db[level];
    for (const System& s : systems) {
      EraValidationRow row;
      row.seed = s.seed;
      row.true_order = static_cast<int>(s.truth.order());
      row.snr_db = snr;
      // Step 3.
      Eigen::VectorXd y = s.y;
      if (std::isfinite(snr)) {
        row.noise_std = std::sqrt(s.mean_square / std::pow(10.0, snr / 10.0));
        std::mt19937_64 rng(splitmix64(s.seed + 1000003ULL * (level + 1)));
        std::normal_distribution<double> noise(0.0, row.noise_std);
        for (int k = 0; k < N; ++k) y[k] += noise(rng);
      }
      // Step 4.
      const Eigen::VectorXcd G = fft.forward(y);
      // Steps 5-6.
      const EraResult era = era_identify(f, G, rate, o.era);
      row.era_runtime_s = era.runtime_s;
      if (era.summary.ok() && era.fit_G_model.size() == M) {
        row.era_ok = true;
        row.era_order = static_cast<int>(era.model.order());
        row.era_fit_pct = frf_fit_pct(s.G_fit, era.fit_G_model);
      }
      const FrequencySubspaceResult sub = frequency_subspace_identify(f, G, rate, o.subspace);
      row.subspace_runtime_s = sub.runtime_s;
      if (sub.summary.ok() && sub.fit_G_model.size() == M) {
        row.subspace_ok = true;
        row.subspace_order = static_cast<int>(sub.model.order());
        row.subspace_fit_pct = frf_fit_pct(s.G_fit, sub.fit_G_model);
      }
      study.rows.push_back(row);
    }
  }
  for (std::size_t level = 0; level < o.snr_db.size(); ++level) {
    std::vector<const EraValidationRow*> rows;
    for (const EraValidationRow& r : study.rows) {
      if (r.snr_db == o.snr_db[level] || (std::isinf(r.snr_db) && std::isinf(o.snr_db[level]))) {
        rows.push_back(&r);
      }
    }
    EraValidationLevel l;
    l.snr_db = o.snr_db[level];
    l.era = statistics(rows, true);
    l.subspace = statistics(rows, false);
    study.levels.push_back(l);
  }
  study.runtime_s = seconds_since(t0);
  return study;
}

std::string format_validation_table(const EraValidationStudy& study) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line,
                "N = %d, %d systems a level (median true order %.1f); fit %% against the "
                "noise-free FRF\n",
                study.record_length, study.levels.empty() ? 0 : study.levels.front().era.count,
                study.median_true_order);
  out << line;
  out << "SNR dB  method    median    p10      min      max   failed  med.order  med.ms\n";
  for (const EraValidationLevel& l : study.levels) {
    for (int k = 0; k < 2; ++k) {
      const FitStatistics& s = k == 0 ? l.era : l.subspace;
      std::snprintf(line, sizeof line,
                    "%6.1f  %-8s %7.2f  %7.2f  %7.2f  %7.2f  %5d  %9.1f  %7.1f\n", l.snr_db,
                    k == 0 ? "ERA" : "subspace", s.median, s.p10, s.min, s.max, s.failures,
                    s.median_order, 1e3 * s.median_runtime_s);
      out << line;
    }
  }
  return out.str();
}

}  // namespace sysid
}  // namespace chatterlab
