#include "app/lobes/lobes_run.h"

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "analysis/common/constants.h"
#include "app/core/format.h"
#include "app/core/hashing.h"
#include "app/lobes/lobes_output.h"
#include "app/report/document.h"
#include "render/gnuplot_backend.h"

namespace chatterlab::app {

using nlohmann::json;

lobes::SemiDiscretizationOptions semi_discretization_options(const lobes::LobesInput& in,
                                                             int steps_per_tooth, int threads) {
  lobes::SemiDiscretizationOptions o;
  o.steps_per_tooth = steps_per_tooth > 0 ? steps_per_tooth : lobes::automatic_steps_per_tooth(in);
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  o.threads = threads > 0 ? threads : hw;
  return o;
}

namespace {

std::string modes_text(const std::vector<ModalParameters>& modes) {
  if (modes.empty()) return "rigid";
  std::string s;
  for (const auto& m : modes) {
    s += (s.empty() ? "" : "; ") + fmt_sig(natural_frequency_hz(m), 4) +
         " Hz (m = " + fmt_sig(m.m_kg, 4) + " kg, c = " + fmt_sig(m.c_kg_s, 4) +
         " kg/s, k = " + fmt_sig(m.k_N_m, 4) + " N/m)";
  }
  return s;
}

json method_row(const std::string& name, const json& j, const std::string& note) {
  const auto depth = j["minimum_limit_depth_mm"];
  return {{"method", name},
          {"minimum", depth.is_null() ? std::string("stable at every speed")
                                      : fmt_sig(depth.get<double>(), 4) + " mm at " +
                                            fmt_sig(j["minimum_at_rpm"].get<double>(), 5) + " rpm"},
          {"runtime_s", fmt_sig(j["runtime_s"].get<double>(), 3)},
          {"note", note}};
}

}  // namespace

int run_lobes(const std::filesystem::path& spec_file, const std::filesystem::path& out,
              const LobesRunOptions& options, std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const LobesSpec spec = load_lobes_spec(spec_file);
  std::ostream& warn = options.warnings != nullptr ? *options.warnings : log;
  for (const auto& w : spec.warnings) warn << "chatterlab lobes: warning: " << w << "\n";
  const lobes::LobesInput& in = spec.input;

  std::optional<lobes::LobesResult> sd;
  std::optional<lobes::ZeroOrderResult> zoa;
  const lobes::SemiDiscretizationOptions so =
      semi_discretization_options(in, spec.steps_per_tooth, options.jobs);
  if (spec.semi_discretization) sd = lobes::semi_discretization(in, so);
  if (spec.zoa) zoa = lobes::zero_order(in);

  json results;
  results["format"] = "chatterlab-lobes-results/1";
  results["spec_sha256"] = sha256_file(spec_file);
  results["max_depth_mm"] = in.max_depth_m * kMToMm;
  json methods = json::object();
  if (sd) {
    methods["semi-discretization"] = lobes_method_json(*sd, true);
    methods["semi-discretization"]["steps_per_tooth"] = so.steps_per_tooth;
    methods["semi-discretization"]["depth_rel_tol"] = so.depth_rel_tol;
  }
  if (zoa) methods["zoa"] = lobes_method_json(zoa->lobes, false);
  results["methods"] = methods;
  std::vector<std::string> warnings = spec.warnings;
  std::filesystem::create_directories(out);

  if (!options.report) {
    results["warnings"] = warnings;
    write_results_json(out / "results.json", results);
    log << "lobes: " << in.spindle_rpm.size() << " speeds; wrote "
        << (out / "results.json").string() << "\n";
    return 0;
  }

  std::filesystem::create_directories(out / "figures");
  try {
    std::vector<LobeCurve> curves;
    if (sd) curves.push_back({"semi-discretization", &*sd, false, true, true});
    if (zoa) curves.push_back({"zero-order (ZOA)", &zoa->lobes, true, true, false});
    render::render_report_figure(lobes_figure(curves, {}, {}, in.max_depth_m),
                                 out / "figures/lobes");
  } catch (const std::exception& e) {
    warnings.push_back(std::string("figure figures/lobes not drawn: ") + e.what());
  }
  results["warnings"] = warnings;
  write_results_json(out / "results.json", results);

  json ctx = spec_document_context(spec_file, results["spec_sha256"].get<std::string>());
  ctx["tool"] =
      std::to_string(in.teeth) + " teeth, radius " + fmt_sig(in.radius_m * kMToMm, 4) + " mm";
  ctx["modal"] = "x: " + modes_text(in.x_modes) + "; y: " + modes_text(in.y_modes);
  ctx["coefficients"] = tooth_coefficients_text(in.Kt_N_m2, in.Kr_N_m2);
  ctx["cut"] = std::string(in.operation == milling::Operation::kDownMilling ? "down-milling"
                                                                            : "up-milling") +
               ", radial immersion " + fmt_sig(in.radial_immersion_m * kMToMm, 4) + " mm";
  set_spec_title(
      ctx, {"stability lobes", "stability lobes", "stability lobes, semi-discretization", "Grid",
            std::to_string(in.spindle_rpm.size()) + " speeds from " +
                fmt_sig(in.spindle_rpm.front(), 5) + " to " + fmt_sig(in.spindle_rpm.back(), 5) +
                " rpm, depths up to " + fmt_sig(in.max_depth_m * kMToMm, 4) + " mm"});
  json rows = json::array();
  std::string summary;
  if (sd) {
    rows.push_back(method_row(
        "semi-discretization", methods["semi-discretization"],
        std::to_string(so.steps_per_tooth) + " intervals per tooth period, multipliers over the " +
            (sd->revolution_period ? "revolution (unequal teeth)" : "tooth period") +
            ", limit within " + fmt_sig(so.depth_rel_tol * 100, 2) + " %"));
    summary = "Semi-discretization minimum " + rows.back()["minimum"].get<std::string>();
  }
  if (zoa) {
    rows.push_back(method_row("zero-order approximation", methods["zoa"],
                              "mean directional matrix over the tooth period; Hopf lobes only"));
    if (summary.empty())
      summary = "Zero-order minimum " + rows.back()["minimum"].get<std::string>();
  }
  ctx["methods"] = rows;
  ctx["summary_line"] = summary;
  ctx["has_warnings"] = !warnings.empty();
  ctx["warnings"] = warnings;
  ctx["fig_lobes"] = "figures/lobes";
  const bool pdf_written =
      write_documents("lobes.html", ctx, out, DocumentOptions{options.pdf, false}, "lobes", log);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "lobes: " << summary << "; wrote " << (out / "index.html").string()
      << (pdf_written ? ", report.pdf" : "") << ", results.json in " << fmt_sig(total, 3) << " s\n";
  return !options.pdf || pdf_written ? 0 : 1;
}

}  // namespace chatterlab::app
