// A single-input single-output discrete state-space model (001 eq. 3.10)
//   x[k+1] = A x[k] + B u[k],   y[k] = C x[k] + D u[k]
// at a sample rate, with its frequency response and poles.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

namespace chatterlab {
namespace sysid {

struct DiscreteStateSpace {
  Eigen::MatrixXd A;     // n x n
  Eigen::VectorXd B;     // n
  Eigen::RowVectorXd C;  // n
  double D = 0.0;
  double sample_rate_hz = 0.0;

  Eigen::Index order() const { return A.rows(); }
};

// G(f) = C (zI - A)^-1 B + D, z = exp(j 2 pi f / rate), at each frequency (one complex LU per
// point: models of up to ~100 states).
Eigen::VectorXcd frequency_response(const DiscreteStateSpace& model,
                                    const Eigen::Ref<const Eigen::VectorXd>& f_hz);

// G(z = 1) = C (I - A)^-1 B + D: the static gain.
double dc_gain(const DiscreteStateSpace& model);

// A continuous-time view of a discrete pole pair: s = rate ln z, fn = |s| / (2 pi),
// zeta = -Re s / |s| (format section 5, ERA step 8).
struct DiscreteMode {
  std::complex<double> z;
  double fn_hz = 0.0;
  double zeta = 0.0;
};

// The eigenvalues of A (any order).
Eigen::VectorXcd poles(const DiscreteStateSpace& model);

// One mode per pole with Im z > 0, sorted by fn; real poles carry no mode.
std::vector<DiscreteMode> modes_of(const Eigen::Ref<const Eigen::VectorXcd>& poles,
                                   double sample_rate_hz);

}  // namespace sysid
}  // namespace chatterlab
