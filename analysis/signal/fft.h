// Real-input FFT with an FFTW plan created once and reused (DESIGN.md: FFT plans reused).
#pragma once

#include <Eigen/Core>
#include <memory>

#include "analysis/common/summary.h"  // InputError

namespace chatterlab {
namespace signal {

// Forward and inverse real FFT of a fixed length n, unnormalised like FFTW:
//   forward:  X[k] = sum_{t=0}^{n-1} x[t] exp(-2 pi i k t / n),  k = 0 .. n/2
//   inverse:  x[t] = sum_{k=0}^{n-1} X[k] exp(+2 pi i k t / n)   (Hermitian X, so
//             inverse(forward(x)) = n x).
// The plans are made once in the constructor (FFTW_ESTIMATE) under a process-wide mutex,
// because FFTW's planner is not thread-safe; executing them is. One object owns its work
// buffers, so one RealFft must not be used from two threads at once: give each thread its
// own.
class RealFft {
 public:
  // @param n  transform length, >= 1
  // @throws InputError if n < 1
  explicit RealFft(Eigen::Index n);
  ~RealFft();
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;
  RealFft(RealFft&&) noexcept;
  RealFft& operator=(RealFft&&) noexcept;

  Eigen::Index size() const;
  Eigen::Index bins() const;  // n/2 + 1

  // @param x  n real samples
  // @return   n/2 + 1 complex bins, k = 0 .. n/2
  // @throws InputError if x.size() != n
  Eigen::VectorXcd forward(const Eigen::Ref<const Eigen::VectorXd>& x);
  // Same, into a caller-owned vector (resized only if its size is not n/2 + 1).
  void forward(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::VectorXcd* out);

  // @param X  n/2 + 1 bins of a Hermitian spectrum (imaginary parts of bin 0 and, for even
  //           n, bin n/2 are ignored)
  // @return   n real samples, unnormalised (divide by n to invert forward)
  // @throws InputError if X.size() != n/2 + 1
  Eigen::VectorXd inverse(const Eigen::Ref<const Eigen::VectorXcd>& X);

 private:
  struct Plans;
  std::unique_ptr<Plans> plans_;
};

}  // namespace signal
}  // namespace chatterlab
