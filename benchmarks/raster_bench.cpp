// Speed of the density rasterizer and of a density figure (`make bench` or
// build/benchmarks/chatterlab_bench --benchmark_filter=Density); figures in docs/rendering.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "render/density_raster.h"
#include "render/gnuplot_backend.h"

namespace {

using namespace chatterlab::render;

// Every revolution of a run overlaid: 7740 revolutions x 1600 samples (12.4 million points) of
// a noisy closed orbit, x against spindle angle, as floats.
struct Revolutions {
  std::vector<float> angle_deg, x_um;
  std::vector<double> mean_angle, mean_x;
};

const Revolutions& revolutions() {
  static const Revolutions r = [] {
    constexpr int kRevolutions = 7740, kSamples = 1600;
    Revolutions d;
    d.angle_deg.reserve(static_cast<std::size_t>(kRevolutions) * kSamples);
    d.x_um.reserve(d.angle_deg.capacity());
    d.mean_angle.resize(kSamples);
    d.mean_x.assign(kSamples, 0.0);
    std::mt19937 rng(1);
    std::normal_distribution<double> n(0.0, 1.0);
    for (int rev = 0; rev < kRevolutions; ++rev) {
      const double gain = 1.0 + 0.03 * n(rng), branch = rev % 2 ? 4.0 : -4.0;
      for (int s = 0; s < kSamples; ++s) {
        const double deg = 360.0 * s / kSamples, t = deg * M_PI / 180.0;
        const double v =
            gain * (18 * std::sin(t) + 6 * std::sin(2 * t + 0.7) + branch * std::sin(3 * t)) +
            0.8 * n(rng);
        d.angle_deg.push_back(static_cast<float>(deg));
        d.x_um.push_back(static_cast<float>(v));
        d.mean_angle[s] = deg;
        d.mean_x[s] += v / kRevolutions;
      }
    }
    return d;
  }();
  return r;
}

// Counting alone into the plot area of a 6.3 x 3.6 in figure at 200 dpi (1084 x 543 px);
// arg 0: whole points, 1: antialiased (4 weighted atomic adds a point).
void BM_DensityCount12M(benchmark::State& state) {
  const Revolutions& r = revolutions();
  DensityOptions o;
  o.style.antialias = state.range(0) != 0;
  count_density(r.angle_deg, r.x_um, {0, 360}, {-35, 30}, 1084, 543, o);  // context, JIT
  for (auto _ : state) {
    const DensityGrid g = count_density(r.angle_deg, r.x_um, {0, 360}, {-35, 30}, 1084, 543, o);
    benchmark::DoNotOptimize(g.counts.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(r.x_um.size()));
  state.SetLabel(density_renderer());
}
BENCHMARK(BM_DensityCount12M)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DensityShade(benchmark::State& state) {
  const Revolutions& r = revolutions();
  const DensityGrid g = count_density(r.angle_deg, r.x_um, {0, 360}, {-35, 30}, 1084, 543);
  for (auto _ : state) {
    const RgbaImage img = shade_density(g, "#0072B2");
    benchmark::DoNotOptimize(img.rgba.data());
  }
}
BENCHMARK(BM_DensityShade)->Unit(benchmark::kMillisecond);

// The whole figure: plan, rasterize, compose with the mean line in gnuplot, PNG at 200 dpi.
void BM_DensityFigurePng12M(benchmark::State& state) {
  const Revolutions& r = revolutions();
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  a.x_label = "spindle angle [deg]";
  a.y_label = "deflection x [um]";
  a.x_range = Range{0, 360};
  a.series.push_back(Series::density(r.angle_deg, r.x_um, "every revolution"));
  a.series.push_back({r.mean_angle, r.mean_x, "mean", SeriesStyle::kLine, "#000000"});
  const auto out = std::filesystem::temp_directory_path() / "chatterlab-bench-density.png";
  for (auto _ : state) render_png(fig, out, 200.0);
  std::filesystem::remove(out);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(r.x_um.size()));
}
BENCHMARK(BM_DensityFigurePng12M)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
