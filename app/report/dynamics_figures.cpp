#include "app/report/dynamics_figures.h"

#include <algorithm>

#include "app/core/format.h"

namespace chatterlab::app {
namespace {

constexpr double kUm = 1e6;
constexpr double kMmPerM = 1e3;

}  // namespace

render::Figure bifurcation_figure(
    const Eigen::Ref<const Eigen::VectorXd>& depth_m,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& samples_m,
    const std::optional<double>& bifurcation_depth_m, bool constant_depth) {
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = 2.1 * static_cast<double>(samples_m.size());
  std::vector<double> x(static_cast<std::size_t>(depth_m.size()));
  for (Eigen::Index i = 0; i < depth_m.size(); ++i) {
    x[static_cast<std::size_t>(i)] =
        constant_depth ? static_cast<double>(i + 1) : depth_m[i] * kMmPerM;
  }
  for (const auto& [name, values] : samples_m) {
    render::Axes& a = fig.panels.emplace_back();
    a.y_label = name + "_n [um]";
    std::vector<double> y(static_cast<std::size_t>(values.size()));
    for (Eigen::Index i = 0; i < values.size(); ++i)
      y[static_cast<std::size_t>(i)] = values[i] * kUm;
    if (bifurcation_depth_m && !y.empty()) {
      const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
      a.series.emplace_back(x, y, name + "_n", render::SeriesStyle::kPoints);
      a.series.emplace_back(
          std::vector<double>{*bifurcation_depth_m * kMmPerM, *bifurcation_depth_m * kMmPerM},
          std::vector<double>{*lo, *hi}, "bifurcation", render::SeriesStyle::kDashedLine,
          "#D55E00");
    } else {
      a.series.emplace_back(x, y, name + "_n", render::SeriesStyle::kPoints);
    }
  }
  fig.panels.back().x_label = constant_depth ? "revolution" : "axial depth of cut [mm]";
  return fig;
}

render::Figure poincare_figure(const std::vector<dynamics::PoincareMap>& maps) {
  render::Figure fig;
  fig.height_in = 2.6 * static_cast<double>(maps.size());
  for (const auto& m : maps) {
    render::Axes& a = fig.panels.emplace_back();
    a.title = "depth " + fmt_sig(m.first_depth_m * kMmPerM, 3) + " to " +
              fmt_sig(m.last_depth_m * kMmPerM, 3) + " mm";
    a.x_label = "x_(n-1) [um]";
    a.y_label = "x_n [um]";
    std::vector<double> px, py;
    for (Eigen::Index i = 0; i < m.points_m.rows(); ++i) {
      px.push_back(m.points_m(i, 0) * kUm);
      py.push_back(m.points_m(i, 1) * kUm);
    }
    a.series.emplace_back(px, py, "", render::SeriesStyle::kPoints, "#0072B2");
    a.legend = render::LegendPosition::kNone;
  }
  return fig;
}

}  // namespace chatterlab::app
