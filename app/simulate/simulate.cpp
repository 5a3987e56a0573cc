#include "app/simulate/simulate.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "analysis/common/constants.h"
#include "analysis/common/modal_parameters.h"
#include "analysis/common/summary.h"
#include "analysis/dynamics/bifurcation.h"
#include "analysis/dynamics/poincare.h"
#include "analysis/dynamics/simulated_bifurcation.h"
#include "analysis/milling/simulation.h"
#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/core/hashing.h"
#include "app/core/parallel.h"
#include "app/report/document.h"
#include "app/report/dynamics_figures.h"
#include "app/report/results_json.h"
#include "render/gnuplot_backend.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

std::vector<double> to_std(const Eigen::VectorXd& v, double scale) {
  std::vector<double> out(static_cast<std::size_t>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i) out[static_cast<std::size_t>(i)] = v[i] * scale;
  return out;
}

render::Figure revolution_figure(const milling::RevolutionRecord& r, int teeth, bool inertial) {
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = inertial ? 6.0 : 4.6;
  const std::vector<double> angle = to_std(r.theta1_rad, kRadToDeg);
  render::Axes& d = fig.panels.emplace_back();
  d.y_label = "deflection [um]";
  d.series.emplace_back(angle, to_std(r.x_m, kMToUm), "x");
  d.series.emplace_back(angle, to_std(r.y_m, kMToUm), "y");
  render::Axes& c = fig.panels.emplace_back();
  c.y_label = "chip thickness [um]";
  for (int p = 0; p < teeth; ++p) {
    c.series.emplace_back(angle, to_std(r.chip_m.col(p), kMToUm), "tooth " + std::to_string(p + 1));
  }
  render::Axes& f = fig.panels.emplace_back();
  f.y_label = "force [N]";
  f.series.emplace_back(angle, to_std(r.Fx_N, 1.0), "cutting Fx");
  f.series.emplace_back(angle, to_std(r.Fy_N, 1.0), "cutting Fy");
  if (inertial) {
    f.series.emplace_back(angle, to_std(r.centrifugal_x_N + r.coriolis_x_N, 1.0), "inertial x",
                          render::SeriesStyle::kDashedLine);
    f.series.emplace_back(angle, to_std(r.centrifugal_y_N + r.coriolis_y_N, 1.0), "inertial y",
                          render::SeriesStyle::kDashedLine);
  }
  f.x_label = "tool angle theta_1 [deg]";
  // Not through d, c, f: emplace_back may have moved the earlier panels.
  for (auto& a : fig.panels) a.x_range = render::Range{0, 360};
  return fig;
}

render::Figure overlay_figure(const milling::CompactTrace& t, int steps_per_revolution) {
  std::vector<float> angle(t.x_m.size()), x_um(t.x_m.size());
  for (std::size_t i = 0; i < t.x_m.size(); ++i) {
    angle[i] = static_cast<float>(
        t.angle_rad[static_cast<Eigen::Index>(i % static_cast<std::size_t>(steps_per_revolution))] *
        kRadToDeg);
    x_um[i] = t.x_m[i] * 1e6f;
  }
  render::Figure fig;
  fig.height_in = 3.6;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "tool angle theta_1 [deg]";
  a.y_label = "deflection x [um]";
  a.x_range = render::Range{0, 360};
  a.series.push_back(
      render::Series::density(std::move(angle), std::move(x_um), "every revolution", "#0072B2"));
  a.series.emplace_back(to_std(t.angle_rad, kRadToDeg), to_std(t.mean_x_m, kMToUm), "mean",
                        render::SeriesStyle::kLine, "#000000");
  return fig;
}

}  // namespace

milling::SimulationOptions simulation_options(const SimulationSpec& s) {
  milling::SimulationOptions o;
  o.teeth = s.teeth;
  o.radius_m = s.radius_m;
  o.modal_x = s.x;
  o.modal_y = s.y;
  for (std::size_t p = 0; p < s.Kt_N_m2.size(); ++p) {
    o.coefficients.push_back(milling::cutting_coefficients(s.Kt_N_m2[p], s.Kr_N_m2.at(p)));
  }
  o.operation = s.operation == "down-milling" ? milling::Operation::kDownMilling
                                              : milling::Operation::kUpMilling;
  o.spindle_rpm = s.spindle_rpm;
  o.feed_per_tooth_m = s.feed_per_tooth_m;
  o.radial_immersion_m = s.radial_immersion_m;
  o.depth = s.depth_start_m != s.depth_end_m
                ? milling::DepthProfile::ramp(s.depth_start_m, s.depth_end_m, *s.revolutions_per_mm)
                : milling::DepthProfile::constant(s.depth_start_m, *s.revolutions);
  o.chip_model = s.chip_model == "numerical" ? milling::ChipModel::kNumerical
                                             : milling::ChipModel::kTraditional;
  o.steps_per_tooth = s.steps_per_tooth;
  o.switching = s.switching == "angle-only" ? milling::SwitchingRule::kAngleOnly
                                            : milling::SwitchingRule::kContact;
  o.euler_order = s.euler_order == "position-first" ? milling::EulerOrder::kPositionFirst
                                                    : milling::EulerOrder::kVelocityFirst;
  o.inertial.enabled = s.inertial;
  o.inertial.eccentricity_m = s.eccentricity_m;
  o.inertial.eccentricity_angle_rad = s.eccentricity_angle_rad;
  return o;
}

int run_simulate(const std::filesystem::path& spec_file, const std::filesystem::path& out,
                 const SimulateOptions& options, std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const SimulationSpec spec = load_simulation_spec(spec_file);
  // Ignored (misspelt) keys are said before the run starts, and kept in results.json.
  std::ostream& warn = options.warnings != nullptr ? *options.warnings : log;
  for (const auto& w : spec.warnings) warn << "chatterlab simulate: warning: " << w << "\n";
  const milling::SimulationOptions o = simulation_options(spec);
  const milling::SimulationGrid grid = milling::simulation_grid(o);

  // What to record: the revolution at the first Poincare depth (else the middle of the run,
  // 000 fig. 5.2 shows 1 mm) in full, and every revolution compactly for the overlay.
  const double shown_depth = spec.poincare_depths_m.empty()
                                 ? 0.5 * (grid.depth_start_m + grid.depth_end_m)
                                 : spec.poincare_depths_m.front();
  milling::RecordingRequest rec;
  if (options.report) {
    rec.full_revolutions = {milling::revolution_at_depth(o, shown_depth)};
    rec.trace_revolutions = grid.revolutions;
  }
  const milling::SimulationResult sim = milling::simulate(o, rec);
  // Revolutions that completed (a diverged run leaves NaN samples after the failure).
  const Eigen::Index done = dynamics::completed_revolutions(sim.samples);

  json results;
  results["format"] = "chatterlab-simulation-results/1";
  results["chip_model"] = spec.chip_model;
  results["switching"] = spec.switching;
  results["euler_order"] = spec.euler_order;
  results["steps_per_tooth"] = spec.steps_per_tooth;
  results["revolutions"] = sim.revolutions;
  results["steps"] = sim.steps;
  results["runtime_s"] = sim.runtime_s;
  results["steps_per_s"] = sim.runtime_s > 0 ? static_cast<double>(sim.steps) / sim.runtime_s : 0.0;
  results["spec_sha256"] = sha256_file(spec_file);
  std::vector<std::string> warnings = spec.warnings;

  std::optional<dynamics::BifurcationResult> bif;
  std::vector<dynamics::PoincareMap> maps;
  results["status"] = sim.summary.ok() ? "ok" : "diverged";
  if (!sim.summary.ok()) {
    // The revolutions before the failure are valid; what follows them is not analysed.
    results["message"] = sim.summary.message;
    results["completed_revolutions"] = done;
    warnings.push_back("the run stopped: " + sim.summary.message + "; the analysis covers the " +
                       std::to_string(done) + " revolutions before it");
  }
  {
    // A diverged run's final growth counts as chatter (simulated_bifurcation.h).
    dynamics::BifurcationOptions bo;
    bo.measurement_noise_m = spec.detector_noise_m;
    bif = dynamics::simulated_run_bifurcation(sim, bo).result;
    if (bif) {
      warnings.insert(warnings.end(), bif->summary.warnings.begin(), bif->summary.warnings.end());
    } else {
      warnings.push_back("too few revolutions for the bifurcation detector");
    }
    // Always present (format section 3): null with the reason when the detector could not run,
    // null alone when the run never changes state.
    results["bifurcation_depth_mm"] = nullptr;
    results["bifurcation_status"] = bif && bif->summary.ok() ? "ok" : "skipped";
    if (!bif) {
      results["bifurcation_skip_reason"] = "too few revolutions for the bifurcation detector";
    }
    if (bif && !bif->summary.ok()) {
      warnings.push_back("bifurcation detection failed: " + bif->summary.message);
      results["bifurcation_skip_reason"] = bif->summary.message;
    } else if (bif) {
      results["bifurcation_depth_mm"] =
          bif->bifurcation_depth_m ? json(*bif->bifurcation_depth_m * kMToMm) : json(nullptr);
      results["depth_profile"] = dynamics::to_string(bif->profile);
      results["verdict"] = dynamics::to_string(bif->verdict);
      json islands = json::array();
      for (const auto& is : bif->islands) {
        islands.push_back({{"onset_depth_mm", is.onset_depth_m * kMToMm},
                           {"end_depth_mm", is.end_depth_m * kMToMm}});
      }
      results["chatter_islands"] = islands;
      results["noise_floor_m"] = bif->noise_floor_m;
    }
    std::vector<double> depths;
    for (double d : spec.poincare_depths_m) depths.push_back(d);
    if (!depths.empty() && done > 0) {
      maps = dynamics::poincare_maps(sim.samples.depth_m.head(done), sim.samples.x_m.head(done),
                                     depths);
      json pj = json::array();
      for (const auto& m : maps) {
        json pts = json::array();
        for (Eigen::Index i = 0; i < m.points_m.rows(); ++i) {
          pts.push_back({m.points_m(i, 0), m.points_m(i, 1)});
        }
        const auto cls =
            dynamics::classify_orbit(m, bif && bif->summary.ok() ? bif->noise_floor_m : 1e-9);
        pj.push_back({{"depth_mm", m.requested_depth_m * kMToMm},
                      {"first_depth_mm", m.first_depth_m * kMToMm},
                      {"last_depth_mm", m.last_depth_m * kMToMm},
                      {"orbit", dynamics::to_string(cls.shape)},
                      {"points_m", pts}});
      }
      results["poincare"] = pj;
    }
  }

  if (!options.report) {
    results["warnings"] = warnings;
    std::filesystem::create_directories(out);
    write_results_json(out / "results.json", results);
    log << "simulate: " << sim.revolutions << " revolutions, " << sim.steps << " steps in "
        << fmt_sig(sim.runtime_s, 3) << " s; wrote " << (out / "results.json").string() << "\n";
    return 0;
  }

  // Figures, in parallel.
  std::filesystem::create_directories(out / "figures");
  struct Job {
    std::string stem;
    render::Figure fig;
  };
  std::vector<Job> jobs;
  const std::optional<double> shown_bif =
      bif && bif->summary.ok() ? bif->bifurcation_depth_m : std::nullopt;
  if (done > 0)
    jobs.push_back(
        {"figures/bifurcation",
         bifurcation_figure(sim.samples.depth_m.head(done),
                            {{"x", sim.samples.x_m.head(done)}, {"y", sim.samples.y_m.head(done)}},
                            shown_bif, grid.depth_per_step_m == 0.0)});
  if (!maps.empty()) jobs.push_back({"figures/poincare", poincare_figure(maps)});
  if (!sim.records.empty() && sim.records[0].x_m.allFinite()) {
    jobs.push_back(
        {"figures/revolution", revolution_figure(sim.records[0], o.teeth, spec.inertial)});
  }
  if (sim.summary.ok() && !sim.trace.x_m.empty()) {  // the trace of a diverged run holds NaN
    jobs.push_back({"figures/overlay", overlay_figure(sim.trace, sim.steps_per_revolution)});
  }
  std::vector<std::string> fig_errors(jobs.size());
  parallel_for(jobs.size(), options.jobs, [&](std::size_t i) {
    try {
      render::render_report_figure(jobs[i].fig, out / jobs[i].stem);
    } catch (const std::exception& e) {
      fig_errors[i] = "figure " + jobs[i].stem + " not drawn: " + e.what();
    }
  });
  for (const auto& e : fig_errors) {
    if (!e.empty()) warnings.push_back(e);
  }
  results["warnings"] = warnings;
  write_results_json(out / "results.json", results);

  // HTML and PDF.
  json ctx = spec_document_context(spec_file, results["spec_sha256"].get<std::string>());
  ctx["tool"] =
      std::to_string(spec.teeth) + " teeth, radius " + fmt_sig(spec.radius_m * kMToMm, 4) + " mm";
  ctx["modal"] =
      "x: m = " + fmt_sig(spec.x.m_kg, 4) + " kg, c = " + fmt_sig(spec.x.c_kg_s, 4) +
      " kg/s, k = " + fmt_sig(spec.x.k_N_m, 4) + " N/m; y: m = " + fmt_sig(spec.y.m_kg, 4) +
      " kg, c = " + fmt_sig(spec.y.c_kg_s, 4) + " kg/s, k = " + fmt_sig(spec.y.k_N_m, 4) + " N/m";
  ctx["coefficients"] = tooth_coefficients_text(spec.Kt_N_m2, spec.Kr_N_m2);
  ctx["cut"] = spec.operation + ", " + fmt_sig(spec.spindle_rpm, 5) + " rpm, feed " +
               fmt_sig(spec.feed_per_tooth_m * kMToMm, 4) + " mm/tooth, radial immersion " +
               fmt_sig(spec.radial_immersion_m * kMToMm, 4) + " mm, depth " +
               fmt_sig(spec.depth_start_m * kMToMm, 3) + " to " +
               fmt_sig(grid.depth_end_m * kMToMm, 3) + " mm over " +
               std::to_string(grid.revolutions) + " revolutions";
  set_spec_title(
      ctx,
      {"simulation", "milling simulation", "milling simulation, bifurcation", "Model",
       spec.chip_model + " chip thickness (" + spec.switching + " switching), symplectic Euler (" +
           spec.euler_order + ") at " + std::to_string(spec.steps_per_tooth) +
           " steps per tooth pass" + (spec.inertial ? ", centrifugal and Coriolis forces" : "")});
  std::string bif_text = "n/a";
  if (bif && bif->summary.ok()) {
    bif_text = bif->bifurcation_depth_m
                   ? fmt_fixed(*bif->bifurcation_depth_m * kMToMm, 2) + " mm"
                   : std::string("none (") + dynamics::to_string(bif->verdict) + ")";
  }
  if (!sim.summary.ok()) {
    bif_text += "; the run diverged after revolution " + std::to_string(done) + " (depth " +
                fmt_sig(sim.samples.depth_m[std::max<Eigen::Index>(done - 1, 0)] * kMToMm, 3) +
                " mm)";
  }
  ctx["bifurcation"] = bif_text;
  ctx["has_bifurcation"] = static_cast<bool>(shown_bif);
  ctx["bifurcation_axis"] =
      grid.depth_per_step_m == 0.0 ? "revolution number (constant depth)" : "axial depth of cut";
  json islands = json::array();
  if (bif && bif->summary.ok()) {
    for (const auto& is : bif->islands) {
      islands.push_back({{"start_mm", fmt_fixed(is.onset_depth_m * kMToMm, 2)},
                         {"end_mm", fmt_fixed(is.end_depth_m * kMToMm, 2)}});
    }
  }
  ctx["islands"] = islands;
  ctx["summary_line"] = "Bifurcation depth " + bif_text + "; " + std::to_string(sim.steps) +
                        " steps in " + fmt_sig(sim.runtime_s, 3) + " s";
  ctx["revolutions"] = sim.revolutions;
  ctx["steps"] = std::to_string(sim.steps);
  ctx["runtime_s"] = fmt_sig(sim.runtime_s, 3);
  ctx["steps_per_s"] = fmt_sig(results["steps_per_s"].get<double>(), 3);
  ctx["criterion"] =
      "Bifurcation depth: where the once-per-revolution samples x_n pass between the chatter-free "
      "orbit and chatter, by the spread of x_n about a local trend against the noise floor "
      "(docs/bifurcation.md); an incline gives the depth where chatter begins, a decline where "
      "it ends.";
  ctx["has_warnings"] = !warnings.empty();
  ctx["warnings"] = warnings;
  ctx["fig_bifurcation"] = "figures/bifurcation";
  ctx["has_poincare"] = !maps.empty();
  ctx["fig_poincare"] = "figures/poincare";
  std::string pd;
  for (const auto& m : maps)
    pd += (pd.empty() ? "" : ", ") + fmt_sig(m.requested_depth_m * kMToMm, 3);
  ctx["poincare_depths"] = pd;
  json shown = json::array();
  if (!sim.records.empty() && sim.records[0].x_m.allFinite()) {
    const auto& r = sim.records[0];
    shown.push_back({{"fig", "figures/revolution"},
                     {"caption", "Revolution " + std::to_string(r.revolution + 1) + " (depth " +
                                     fmt_sig(r.depth_m[0] * kMToMm, 3) +
                                     " mm): deflection, chip thickness per tooth and forces" +
                                     (spec.inertial ? " with the inertial forces (000 figs 7.3-7.4)"
                                                    : " (000 fig. 5.2)") +
                                     "."}});
  }
  ctx["revolutions_shown"] = shown;
  ctx["fig_overlay"] = "figures/overlay";
  ctx["overlay_points"] = std::to_string(sim.trace.x_m.size());

  const bool pdf_written = write_documents("simulation.html", ctx, out,
                                           DocumentOptions{options.pdf, false}, "simulate", log);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "simulate: " << sim.revolutions << " revolutions, " << sim.steps << " steps in "
      << fmt_sig(sim.runtime_s, 3) << " s; bifurcation depth " << bif_text << "; wrote "
      << (out / "index.html").string() << (pdf_written ? ", report.pdf" : "")
      << ", results.json in " << fmt_sig(total, 3) << " s\n";
  return !options.pdf || pdf_written ? 0 : 1;
}

}  // namespace chatterlab::app
