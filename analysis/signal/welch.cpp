#include "analysis/signal/welch.h"

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/signal/fft.h"

namespace chatterlab {
namespace signal {

CrossSpectra welch_cross_spectra(const Eigen::Ref<const Eigen::VectorXd>& reference,
                                 const std::vector<Eigen::VectorXd>& channels, int segment,
                                 double fs_hz) {
  const Eigen::Index n = reference.size();
  require_rule(std::isfinite(fs_hz) && fs_hz > 0.0, "sample_rate_hz", fs_hz, "must be > 0");
  require_rule(segment >= 8 && segment % 2 == 0, "segment_samples", segment,
               "must be even and >= 8");
  require_rule(segment <= n, "segment_samples", segment,
               "must be at most the record's length (" + std::to_string(n) + " samples)");
  require_rule(reference.allFinite(), "reference channel", "a non-finite sample", "must be finite");
  for (const auto& x : channels) {
    require_rule(x.size() == n, "channel length", x.size(),
                 "must equal the reference's (" + std::to_string(n) + ")");
    require_rule(x.allFinite(), "channel", "a non-finite sample", "must be finite");
  }
  const int bins = segment / 2 + 1;
  const int step = segment / 2;
  CrossSpectra out;
  out.segments = static_cast<int>((n - segment) / step + 1);
  out.f_hz = Eigen::VectorXd::LinSpaced(bins, 0.0, 0.5 * fs_hz);
  out.S_rr = Eigen::VectorXd::Zero(bins);
  out.S_rx.assign(channels.size(), Eigen::VectorXcd::Zero(bins));
  out.S_xx.assign(channels.size(), Eigen::VectorXd::Zero(bins));
  Eigen::VectorXd w(segment);
  for (int i = 0; i < segment; ++i) w[i] = 0.5 * (1.0 - std::cos(kTwoPi * i / segment));
  RealFft fft(segment);
  Eigen::VectorXd buf(segment);
  Eigen::VectorXcd R(bins), X(bins);
  for (int s = 0; s < out.segments; ++s) {
    const Eigen::Index start = static_cast<Eigen::Index>(s) * step;
    const auto seg = reference.segment(start, segment);
    buf = (seg.array() - seg.mean()) * w.array();
    fft.forward(buf, &R);
    out.S_rr += R.cwiseAbs2();
    for (std::size_t c = 0; c < channels.size(); ++c) {
      const auto xs = channels[c].segment(start, segment);
      buf = (xs.array() - xs.mean()) * w.array();
      fft.forward(buf, &X);
      out.S_rx[c].array() += R.array().conjugate() * X.array();
      out.S_xx[c] += X.cwiseAbs2();
    }
  }
  Eigen::VectorXd scale =
      Eigen::VectorXd::Constant(bins, 2.0 / (out.segments * fs_hz * w.squaredNorm()));
  scale[0] *= 0.5;
  scale[bins - 1] *= 0.5;
  out.S_rr.array() *= scale.array();
  for (std::size_t c = 0; c < channels.size(); ++c) {
    out.S_rx[c].array() *= scale.array();
    out.S_xx[c].array() *= scale.array();
  }
  return out;
}

}  // namespace signal
}  // namespace chatterlab
