#include "analysis/sysid/frequency_subspace.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/common/statistics.h"
#include "analysis/common/stopwatch.h"
#include "analysis/sysid/era.h"
#include "analysis/sysid/gavish_donoho.h"

namespace chatterlab {
namespace sysid {
namespace {

using Clock = SteadyClock;

// Row k: C (z_k I - A)^-1 (step 7). With the complex Schur form A = Z T Z^*, T upper
// triangular, x (z I - T) = C Z is solved column by column, x_j = (c_j + sum_{i<j} x_i T_ij)
// / (z - T_jj), and C (zI - A)^-1 = x Z^*.
Eigen::MatrixXcd resolvent_rows(const Eigen::MatrixXd& A, const Eigen::RowVectorXd& C,
                                const Eigen::VectorXcd& z) {
  const Eigen::Index n = A.rows();
  Eigen::MatrixXcd out(z.size(), n);
  if (n == 0) return out;
  Eigen::ComplexSchur<Eigen::MatrixXcd> schur(A.cast<std::complex<double>>());
  if (schur.info() != Eigen::Success) {
    throw std::runtime_error("the complex Schur form of A did not converge");
  }
  const Eigen::MatrixXcd& T = schur.matrixT();
  const Eigen::MatrixXcd& Z = schur.matrixU();
  const Eigen::RowVectorXcd c = C.cast<std::complex<double>>() * Z;
  const Eigen::MatrixXcd Zh = Z.adjoint();
  Eigen::RowVectorXcd x(n);
  for (Eigen::Index k = 0; k < z.size(); ++k) {
    for (Eigen::Index j = 0; j < n; ++j) {
      std::complex<double> acc = c[j];
      for (Eigen::Index i = 0; i < j; ++i) acc += x[i] * T(i, j);
      x[j] = acc / (z[k] - T(j, j));
    }
    out.row(k) = x * Zh;
  }
  return out;
}

}  // namespace

FrequencySubspaceResult frequency_subspace_identify(const Eigen::Ref<const Eigen::VectorXd>& f,
                                                    const Eigen::Ref<const Eigen::VectorXcd>& G,
                                                    double rate,
                                                    const FrequencySubspaceOptions& o) {
  FrequencySubspaceResult out;
  const auto t0 = Clock::now();
  try {
    require_rule(o.max_order >= 1, "max_order", o.max_order, "must be >= 1");
    require_rule(
        o.order >= 0 && o.order <= o.max_order, "order", o.order,
        "must be 0 (Gavish-Donoho rule) or in 1 .. max_order = " + std::to_string(o.max_order));
    require_rule(o.block_rows >= 0, "block_rows", o.block_rows, "must be 0 (default) or >= 2");
    const int q = o.block_rows == 0 ? 2 * o.max_order : o.block_rows;
    require_rule(q >= 2 && q > o.order, "block_rows", q, "must be >= 2 and > order");
    out.block_rows = q;
    require_rule(std::isfinite(rate) && rate > 0.0, "sample_rate_hz", rate,
                 "must be finite and > 0");
    const Eigen::Index K = f.size();
    require_rule(K >= 2, "freq_hz", std::to_string(K) + " points", "needs at least 2 points");
    require_rule(G.size() == K, "FRF values", G.size(), "must be as many as freq_hz");
    const double nyquist = 0.5 * rate;
    int edges = 0;  // points at 0 or rate/2: no imaginary column (step 2)
    for (Eigen::Index k = 0; k < K; ++k) {
      require_rule(std::isfinite(f[k]), "freq_hz", f[k], "must be finite");
      require_rule(std::isfinite(G[k].real()) && std::isfinite(G[k].imag()),
                   "FRF at " + std::to_string(f[k]) + " Hz", G[k], "must be finite");
      require_rule(f[k] >= 0.0, "freq_hz", f[k], "must be >= 0");
      require_rule(f[k] <= nyquist * (1.0 + 1e-12), "freq_hz", f[k],
                   "must be <= sample_rate_hz / 2 = " + std::to_string(nyquist));
      require_rule(k == 0 || f[k] > f[k - 1], "freq_hz", f[k], "must rise strictly");
      if (f[k] == 0.0 || f[k] >= nyquist * (1.0 - 1e-12)) ++edges;
    }
    const Eigen::Index L = 2 * K - edges;
    out.real_columns = static_cast<int>(L);
    require_rule(L >= 2 * q, "freq_hz", std::to_string(K) + " points",
                 "too few for block_rows = " + std::to_string(q) +
                     ": 2 points - (points at 0 and rate/2) must be >= 2 block_rows");
    const double scale = std::sqrt(G.squaredNorm() / static_cast<double>(K));
    require_rule(scale > 0.0, "FRF", "zero at every point", "has no dynamics to identify");

    // Steps 1-3: [W_re; G_re]^T (L x 2q; G scaled to unit rms for the conditioning of the QR:
    // it changes no column space), its QR, and R22 = the lower right block of R^T.
    Eigen::VectorXcd z(K);
    Eigen::MatrixXd Ht(L, 2 * q);
    Eigen::Index row = 0;
    for (Eigen::Index k = 0; k < K; ++k) {
      const double w = kTwoPi * f[k] / rate;
      z[k] = std::polar(1.0, w);
      const std::complex<double> g = G[k] / scale;
      const bool edge = f[k] == 0.0 || f[k] >= nyquist * (1.0 - 1e-12);
      for (int i = 0; i < q; ++i) {
        const std::complex<double> zi = std::polar(1.0, i * w);
        const std::complex<double> zg = zi * g;
        Ht(row, i) = zi.real();
        Ht(row, q + i) = zg.real();
        if (!edge) {
          Ht(row + 1, i) = zi.imag();
          Ht(row + 1, q + i) = zg.imag();
        }
      }
      row += edge ? 1 : 2;
    }
    const auto t_svd = Clock::now();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(Ht);
    const Eigen::MatrixXd R22 =
        qr.matrixQR().block(q, q, q, q).triangularView<Eigen::Upper>().toDenseMatrix().transpose();
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(R22, Eigen::ComputeThinU);
    out.svd_s = seconds_since(t_svd);
    out.singular_values = svd.singularValues();
    const Eigen::VectorXd& s = out.singular_values;

    // Step 4: the order.
    int r = 0;
    if (o.order > 0) {
      r = o.order;
    } else {
      out.aspect_ratio = static_cast<double>(q) / static_cast<double>(L - q);
      const double floor = std::sqrt(static_cast<double>(q) * static_cast<double>(L)) *
                           std::numeric_limits<double>::epsilon() * Ht.rightCols(q).norm();
      out.threshold = std::max(gavish_donoho_omega(out.aspect_ratio) * median(s), floor);
      while (r < q && s[r] > out.threshold) ++r;
    }
    out.order_by_threshold = r;
    r = std::min({r, o.max_order, q - 1});
    if (r == 0) {
      std::ostringstream m;
      m << "the subspace method kept no state: the largest singular value " << s[0]
        << " is not above the threshold " << out.threshold;
      out.summary.fail(m.str());
      out.runtime_s = seconds_since(t0);
      return out;
    }

    // Step 5: A and C by shift invariance.
    const Eigen::MatrixXd O = svd.matrixU().leftCols(r);
    DiscreteStateSpace& model = out.model;
    model.sample_rate_hz = rate;
    model.C = O.row(0);
    model.A = O.topRows(q - 1).colPivHouseholderQr().solve(O.bottomRows(q - 1));

    // Step 6: the stable pair.
    const Eigen::VectorXcd p_full = poles(model);
    if (p_full.cwiseAbs().maxCoeff() >= kStableRadius) {
      DiscreteStateSpace pair = model;
      pair.B = Eigen::VectorXd::Zero(r);
      const StableSplit split = stable_part(pair);
      if (!split.summary.ok()) {
        out.summary.fail(split.summary.message);
        out.runtime_s = seconds_since(t0);
        return out;
      }
      model.A = split.stable.A;
      model.C = split.stable.C;
      out.unstable_removed = split.removed;
    }

    // Step 7: B and D by least squares on the stacked real and imaginary parts.
    const Eigen::Index n = model.order();
    const Eigen::MatrixXcd Phi = resolvent_rows(model.A, model.C, z);
    Eigen::MatrixXd X(2 * K, n + 1);
    Eigen::VectorXd rhs(2 * K);
    X.topLeftCorner(K, n) = Phi.real();
    X.bottomLeftCorner(K, n) = Phi.imag();
    X.col(n).head(K).setOnes();
    X.col(n).tail(K).setZero();
    rhs.head(K) = G.real();
    rhs.tail(K) = G.imag();
    const Eigen::VectorXd theta = X.colPivHouseholderQr().solve(rhs);
    model.B = theta.head(n);
    model.D = theta[n];

    // Step 8 and the model's views.
    out.poles = poles(model);
    out.modes = modes_of(out.poles, rate);
    out.dc_gain = dc_gain(model);
    std::vector<Eigen::Index> keep;
    for (Eigen::Index k = 0; k < K; ++k) {
      if (f[k] > 0.0) keep.push_back(k);
    }
    const Eigen::Index nk = static_cast<Eigen::Index>(keep.size());
    out.fit_f_hz.resize(nk);
    out.fit_G.resize(nk);
    out.fit_G_model.resize(nk);
    const Eigen::VectorXcd Bc = model.B.cast<std::complex<double>>();
    for (Eigen::Index i = 0; i < nk; ++i) {
      const Eigen::Index k = keep[static_cast<std::size_t>(i)];
      out.fit_f_hz[i] = f[k];
      out.fit_G[i] = G[k];
      out.fit_G_model[i] = (Phi.row(k) * Bc)(0) + model.D;
    }
    out.fit_pct = frf_fit_pct(out.fit_G, out.fit_G_model);
    out.summary.succeed();
    if (out.order_by_threshold > r) {
      std::ostringstream m;
      m << "the threshold kept " << out.order_by_threshold
        << " singular values; the order is capped at " << r;
      out.summary.warnings.push_back(m.str());
    }
    if (out.unstable_removed > 0) {
      out.summary.warnings.push_back(std::to_string(out.unstable_removed) +
                                     " unstable states removed (ordered Schur split)");
    }
  } catch (const InputError& e) {
    out.summary.fail(e.what());
  } catch (const std::runtime_error& e) {
    out.summary.fail(e.what());
  }
  out.runtime_s = seconds_since(t0);
  return out;
}

}  // namespace sysid
}  // namespace chatterlab
