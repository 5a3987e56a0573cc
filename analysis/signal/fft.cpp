#include "analysis/signal/fft.h"

#include <fftw3.h>

#include <mutex>
#include <string>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace signal {
namespace {

// FFTW's planner (and fftw_destroy_plan) is not thread-safe: serialise them process-wide.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

}  // namespace

struct RealFft::Plans {
  Eigen::Index n = 0;
  double* time = nullptr;        // n samples
  fftw_complex* freq = nullptr;  // n/2 + 1 bins
  fftw_plan forward = nullptr;   // time -> freq
  fftw_plan inverse = nullptr;   // freq -> time (destroys freq, refilled on every call)

  explicit Plans(Eigen::Index length) : n(length) {
    std::lock_guard<std::mutex> lock(planner_mutex());
    const int ni = static_cast<int>(n);
    time = fftw_alloc_real(static_cast<size_t>(n));
    freq = fftw_alloc_complex(static_cast<size_t>(n / 2 + 1));
    forward = fftw_plan_dft_r2c_1d(ni, time, freq, FFTW_ESTIMATE);
    inverse = fftw_plan_dft_c2r_1d(ni, freq, time, FFTW_ESTIMATE);
  }
  ~Plans() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    if (forward) fftw_destroy_plan(forward);
    if (inverse) fftw_destroy_plan(inverse);
    fftw_free(time);
    fftw_free(freq);
  }
  Plans(const Plans&) = delete;
  Plans& operator=(const Plans&) = delete;
};

RealFft::RealFft(Eigen::Index n) {
  if (n < 1) throw InputError("fft length n = " + std::to_string(n) + ": must be >= 1");
  plans_ = std::make_unique<Plans>(n);
  if (!plans_->forward || !plans_->inverse || !plans_->time || !plans_->freq) {
    throw std::runtime_error("FFTW could not plan a real FFT of length " + std::to_string(n));
  }
}

RealFft::~RealFft() = default;
RealFft::RealFft(RealFft&&) noexcept = default;
RealFft& RealFft::operator=(RealFft&&) noexcept = default;

Eigen::Index RealFft::size() const { return plans_->n; }
Eigen::Index RealFft::bins() const { return plans_->n / 2 + 1; }

Eigen::VectorXcd RealFft::forward(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Eigen::VectorXcd out(bins());
  forward(x, &out);
  return out;
}

void RealFft::forward(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::VectorXcd* out) {
  const Eigen::Index n = plans_->n;
  if (x.size() != n) {
    throw InputError("fft input has " + std::to_string(x.size()) + " samples: plan length is " +
                     std::to_string(n));
  }
  for (Eigen::Index t = 0; t < n; ++t) plans_->time[t] = x[t];
  fftw_execute(plans_->forward);
  const Eigen::Index nb = bins();
  if (out->size() != nb) out->resize(nb);
  for (Eigen::Index k = 0; k < nb; ++k) {
    (*out)[k] = std::complex<double>(plans_->freq[k][0], plans_->freq[k][1]);
  }
}

Eigen::VectorXd RealFft::inverse(const Eigen::Ref<const Eigen::VectorXcd>& X) {
  const Eigen::Index nb = bins();
  if (X.size() != nb) {
    throw InputError("inverse fft input has " + std::to_string(X.size()) +
                     " bins: plan needs n/2 + 1 = " + std::to_string(nb));
  }
  for (Eigen::Index k = 0; k < nb; ++k) {
    plans_->freq[k][0] = X[k].real();
    plans_->freq[k][1] = X[k].imag();
  }
  fftw_execute(plans_->inverse);
  return Eigen::Map<const Eigen::VectorXd>(plans_->time, plans_->n);
}

}  // namespace signal
}  // namespace chatterlab
