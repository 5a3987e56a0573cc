#include "app/lobes/lobes_output.h"

#include <cmath>
#include <limits>

#include "analysis/common/constants.h"

namespace chatterlab::app {

using nlohmann::json;

const char* format_boundary_type(lobes::BoundaryType t) {
  return t == lobes::BoundaryType::kHopf ? "hopf" : "flip";
}

std::optional<LobeMinimum> lobe_minimum(const lobes::LobesResult& r) {
  std::optional<LobeMinimum> best;
  for (const auto& s : r.speeds) {
    if (s.limit_depth_m && (!best || *s.limit_depth_m < best->depth_m)) {
      best = LobeMinimum{*s.limit_depth_m, s.spindle_rpm};
    }
  }
  return best;
}

json lobes_method_json(const lobes::LobesResult& r, bool semi_discretization) {
  json rpm = json::array(), depth = json::array(), type = json::array(), hz = json::array();
  json mu_re = json::array(), mu_im = json::array();
  for (const auto& s : r.speeds) {
    rpm.push_back(s.spindle_rpm);
    depth.push_back(s.limit_depth_m ? json(*s.limit_depth_m * kMToMm) : json(nullptr));
    hz.push_back(s.chatter_hz ? json(*s.chatter_hz) : json(nullptr));
    type.push_back(s.type ? json(format_boundary_type(*s.type)) : json(nullptr));
    mu_re.push_back(s.limit_depth_m ? json(s.critical_multiplier.real()) : json(nullptr));
    mu_im.push_back(s.limit_depth_m ? json(s.critical_multiplier.imag()) : json(nullptr));
  }
  json j;
  j["spindle_rpm"] = rpm;
  j["limit_depth_mm"] = depth;
  if (semi_discretization) j["type"] = type;
  j["chatter_hz"] = hz;
  j["runtime_s"] = r.runtime_s;
  const auto min = lobe_minimum(r);
  j["minimum_limit_depth_mm"] = min ? json(min->depth_m * kMToMm) : json(nullptr);
  j["minimum_at_rpm"] = min ? json(min->spindle_rpm) : json(nullptr);
  if (semi_discretization) {
    j["period"] = r.revolution_period ? "revolution" : "tooth";
    j["critical_multiplier_re"] = mu_re;
    j["critical_multiplier_im"] = mu_im;
  }
  return j;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Okabe-Ito colours, as the rest of the report.
constexpr const char* kBlue = "#0072B2";
constexpr const char* kOrange = "#E69F00";
constexpr const char* kGreen = "#009E73";
constexpr const char* kVermillion = "#D55E00";
constexpr const char* kBlack = "#000000";
constexpr const char* kPurple = "#CC79A7";

// A colour per curve, in the order the curves come (Okabe-Ito, measured points excepted).
constexpr const char* kCurveColours[] = {kBlue, kOrange, "#56B4E9", "#999999", "#F0E442", kPurple};

}  // namespace

render::Figure lobes_figure(const std::vector<LobeCurve>& curves,
                            const std::vector<MeasuredPoint>& measured,
                            const std::vector<Hysteresis>& hysteresis, double max_depth_m) {
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = 5.4;
  render::Axes& d = fig.panels.emplace_back();
  d.y_label = "axial depth [mm]";
  d.relative_height = 2.0;
  d.y_range = render::Range{0.0, max_depth_m * kMToMm};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const auto& c = curves[i];
    std::vector<double> x, y;
    for (const auto& s : c.result->speeds) {
      x.push_back(s.spindle_rpm);
      y.push_back(s.limit_depth_m ? *s.limit_depth_m * kMToMm : kNaN);
      lo = std::min(lo, s.spindle_rpm);
      hi = std::max(hi, s.spindle_rpm);
    }
    d.series.emplace_back(std::move(x), std::move(y), c.label,
                          c.dashed ? render::SeriesStyle::kDashedLine : render::SeriesStyle::kLine,
                          kCurveColours[i % std::size(kCurveColours)]);
  }
  // Points, and segments as x, y pairs with NaN between them.
  std::vector<double> sx, sy, cx, cy, bx, by, hx, hy, rsx, rsy, rcx, rcy;
  const auto segment = [](std::vector<double>& x, std::vector<double>& y, double rpm, double a,
                          double b) {
    x.insert(x.end(), {rpm, rpm, kNaN});
    y.insert(y.end(), {a * kMToMm, b * kMToMm, kNaN});
  };
  for (const auto& p : measured) {
    if (!p.ramp && p.chatter) {
      (*p.chatter ? cx : sx).push_back(p.spindle_rpm);
      (*p.chatter ? cy : sy).push_back(p.depth_low_m * kMToMm);
    }
    for (const auto& [a, b] : p.stable_m) segment(rsx, rsy, p.spindle_rpm, a, b);
    for (const auto& [a, b] : p.chatter_m) segment(rcx, rcy, p.spindle_rpm, a, b);
    if (p.bifurcation_depth_m) {
      bx.push_back(p.spindle_rpm);
      by.push_back(*p.bifurcation_depth_m * kMToMm);
    }
    lo = std::min(lo, p.spindle_rpm);
    hi = std::max(hi, p.spindle_rpm);
  }
  for (const auto& h : hysteresis) {
    segment(hx, hy, h.spindle_rpm, std::min(h.onset_m, h.end_m), std::max(h.onset_m, h.end_m));
  }
  if (!rsx.empty()) {
    d.series.emplace_back(std::move(rsx), std::move(rsy), "ramp: stable part",
                          render::SeriesStyle::kLine, kGreen);
  }
  if (!rcx.empty()) {
    d.series.emplace_back(std::move(rcx), std::move(rcy), "ramp: chatter part",
                          render::SeriesStyle::kLine, kVermillion);
  }
  if (!hx.empty()) {
    d.series.emplace_back(std::move(hx), std::move(hy), "hysteresis band",
                          render::SeriesStyle::kLinePoints, kPurple);
  }
  if (!sx.empty()) {
    d.series.emplace_back(std::move(sx), std::move(sy), "measured: stable",
                          render::SeriesStyle::kPoints, kGreen);
  }
  if (!cx.empty()) {
    d.series.emplace_back(std::move(cx), std::move(cy), "measured: chatter",
                          render::SeriesStyle::kPoints, kVermillion);
  }
  if (!bx.empty()) {
    d.series.emplace_back(std::move(bx), std::move(by), "measured bifurcation depth",
                          render::SeriesStyle::kPoints, kBlack);
  }
  render::Axes& f = fig.panels.emplace_back();
  f.y_label = "chatter frequency [Hz]";
  f.x_label = "spindle speed [rpm]";
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const auto& c = curves[i];
    if (!c.frequencies) continue;
    const char* colour = kCurveColours[i % std::size(kCurveColours)];
    if (!c.typed) {
      std::vector<double> x, y;
      for (const auto& s : c.result->speeds) {
        x.push_back(s.spindle_rpm);
        y.push_back(s.chatter_hz ? *s.chatter_hz : kNaN);
      }
      f.series.emplace_back(
          std::move(x), std::move(y), c.label,
          c.dashed ? render::SeriesStyle::kDashedLine : render::SeriesStyle::kPoints, colour);
      continue;
    }
    std::vector<double> fx, fy, hx2, hy2;
    for (const auto& s : c.result->speeds) {
      if (!s.chatter_hz || !s.type) continue;
      const bool hopf = *s.type == lobes::BoundaryType::kHopf;
      (hopf ? hx2 : fx).push_back(s.spindle_rpm);
      (hopf ? hy2 : fy).push_back(*s.chatter_hz);
    }
    if (!hx2.empty()) {
      f.series.emplace_back(std::move(hx2), std::move(hy2), c.label + ": Hopf",
                            render::SeriesStyle::kPoints, colour);
    }
    if (!fx.empty()) {
      f.series.emplace_back(std::move(fx), std::move(fy), c.label + ": flip",
                            render::SeriesStyle::kPoints, kVermillion);
    }
  }
  // Not through d or f: emplace_back may have moved the first panel. Legends beside the plots:
  // a campaign's diagram has up to a dozen entries, which above or inside would hide the lobes.
  for (auto& a : fig.panels) {
    if (hi > lo) a.x_range = render::Range{lo, hi};
    a.legend = render::LegendPosition::kOutsideRight;
  }
  return fig;
}

}  // namespace chatterlab::app
