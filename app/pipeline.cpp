#include "app/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

#include "app/hashing.h"
#include "app/parallel.h"
#include "app/signals.h"
#include "app/validate.h"

namespace chatterlab::app {
namespace {

std::string signal_label(const TestSpec& t) {
  return (t.id.empty() ? "" : t.id + "/") + t.data.relative_file;
}

void run_dyno_record(const TestSpec& t, const PipelineOptions& o, TestOutcome& out) {
  const SignalTable table = SignalTable::open(t.data, signal_label(t));
  const Eigen::VectorXd fx = table.channel("Fx", t.channel("Fx"));
  const Eigen::VectorXd fy = table.channel("Fy", t.channel("Fy"));
  const ChannelSpec zero_cal = t.channel("zero");
  const Eigen::VectorXd zero = table.channel("zero", zero_cal);
  cutting::DynoOptions opt = o.dyno;
  if (zero_cal.threshold) opt.zero_threshold_V = *zero_cal.threshold;
  DynoRecordOutcome d;
  d.feed_per_tooth_m = t.dyno->feed_per_tooth_m;
  d.axial_depth_m = t.dyno->axial_depth_m;
  d.spindle_rpm = t.dyno->spindle_rpm;
  d.result = cutting::analyse_slot_record(fx, fy, zero, t.sample_rate_hz, t.dyno->spindle_rpm, opt);
  out.warnings.insert(out.warnings.end(), d.result.summary.warnings.begin(),
                      d.result.summary.warnings.end());
  if (!d.result.summary.ok) {
    out.status.fail(signal_label(t) + ": " + d.result.summary.message);
    return;
  }
  out.dyno = std::move(d);
  out.status.succeed();
}

// The tool mode of a tap test: the fitted mode with the largest peak receptance 1/(c wn)
// (the most flexible one, which dominates the cut's deflection).
std::optional<frf::Mode> dominant_mode(const TestOutcome& t) {
  if (!t.status.ok || !t.tap || !t.tap->fit_ok || t.tap->modes.empty()) return std::nullopt;
  const frf::Mode* best = nullptr;
  for (const auto& m : t.tap->modes) {
    const double peak = 1.0 / (m.c_kg_s * 2 * M_PI * m.fn_hz);
    if (!best || peak > 1.0 / (best->c_kg_s * 2 * M_PI * best->fn_hz)) best = &m;
  }
  return *best;
}

CutStepInputs cut_inputs(const CampaignResults& r) {
  CutStepInputs in;
  in.tool = r.campaign.tool;
  for (const auto& t : r.tests) {
    if (t.spec->kind != "tap" || !t.spec->tap) continue;
    const auto m = dominant_mode(t);
    if (!m) continue;
    auto& slot = t.spec->tap->axis == "x" ? in.hammer_x : in.hammer_y;
    if (!slot) {
      slot = m;
      in.hammer_source += (in.hammer_source.empty() ? "" : ", ") + t.spec->id;
    }
  }
  if (r.dyno_group && r.dyno_group->summary.ok) in.coefficients = r.dyno_group->fit.coefficients;
  return in;
}

void run_cut(const TestSpec& t, const CutStepInputs& in, const CutStepOptions& o,
             TestOutcome& out) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    CutOutcome c = run_cut_test(t, in, o);
    out.warnings.insert(out.warnings.end(), c.warnings.begin(), c.warnings.end());
    if (c.summary.ok) {
      out.status.succeed();
    } else {
      out.status.fail(c.summary.message);
    }
    out.cut = std::move(c);
  } catch (const std::exception& e) {
    out.status.fail(e.what());
  }
  out.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void run_test(const TestSpec& t, const PipelineOptions& o, TestOutcome& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out.spec = &t;
  out.warnings = t.warnings;
  if (!t.usable()) {
    std::string why;
    for (const auto& e : t.errors) why += (why.empty() ? "" : "; ") + e;
    out.status.fail(why);
    return;
  }
  try {
    if (t.kind == "tap") {
      TapOutcome tap = run_tap_test(t, o.tap);
      out.warnings.insert(out.warnings.end(), tap.warnings.begin(), tap.warnings.end());
      if (tap.summary.ok) {
        out.status.succeed();
      } else {
        out.status.fail(tap.summary.message);
      }
      out.tap = std::move(tap);
    } else if (t.kind == "dyno-slot") {
      run_dyno_record(t, o, out);
    }  // cut tests run afterwards (run_campaign): they need the tap and dyno results
  } catch (const std::exception& e) {
    out.status.fail(e.what());
  }
  out.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

DynoGroupOutcome run_dyno_group(const CampaignResults& r, const PipelineOptions& o) {
  DynoGroupOutcome g;
  std::vector<double> feeds, ft, fr, depth;
  int members = 0;
  for (const auto& t : r.tests) {
    if (t.spec->kind != "dyno-slot") continue;
    ++members;
    if (!t.dyno) continue;
    g.test_ids.push_back(t.spec->id);
    feeds.push_back(t.dyno->feed_per_tooth_m);
    ft.push_back(t.dyno->result.mean_Ft_N);
    fr.push_back(t.dyno->result.mean_Fr_N);
    depth.push_back(t.dyno->axial_depth_m);
  }
  if (r.campaign.tool && r.campaign.tool->teeth != 2) {
    g.summary.fail(
        "the slot method of 000 sec. 3.2 assumes a two-tooth tool (one tooth cutting "
        "at a time); campaign.yaml tool.teeth = " +
        std::to_string(r.campaign.tool->teeth));
    return g;
  }
  if (feeds.size() < 2) {
    g.summary.fail(std::to_string(feeds.size()) + " of " + std::to_string(members) +
                   " dyno-slot records analysed: a line fit needs at least two feeds");
    return g;
  }
  const auto map = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  };
  try {
    g.fit = cutting::fit_slot_coefficients(map(feeds), map(ft), map(fr), map(depth), o.dyno);
    g.summary = g.fit.summary;
  } catch (const std::exception& e) {
    g.summary.fail(e.what());
  }
  return g;
}

}  // namespace

const TestOutcome* identification_source(const CampaignResults& r) {
  const TestOutcome* ramped = nullptr;
  for (const auto& t : r.tests) {
    if (!t.status.ok || !t.cut || !t.cut->estimation.summary.ok) continue;
    if (!t.cut->ramped) return &t;
    if (!ramped) ramped = &t;
  }
  return ramped;
}

CampaignResults run_campaign(CampaignSpec campaign, const PipelineOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  CampaignResults r;
  r.campaign = std::move(campaign);
  r.options = options;
  for (auto& t : r.campaign.tests) check_signals(t);
  r.tests.resize(r.campaign.tests.size());

  parallel_for(r.tests.size(), options.jobs,
               [&](std::size_t i) { run_test(r.campaign.tests[i], options, r.tests[i]); });

  if (std::any_of(r.tests.begin(), r.tests.end(),
                  [](const TestOutcome& t) { return t.spec->kind == "dyno-slot"; })) {
    r.dyno_group = run_dyno_group(r, options);
  }
  // Cut tests use the hammer-test modal parameters and dynamometer coefficients (000 sec. 5.1).
  r.cut_inputs = cut_inputs(r);
  std::vector<std::size_t> cuts;
  for (std::size_t i = 0; i < r.tests.size(); ++i) {
    if (r.campaign.tests[i].kind == "cut" && r.campaign.tests[i].usable()) cuts.push_back(i);
  }
  CutStepOptions cut_options;
  cut_options.estimation = r.campaign.estimation;
  cut_options.estimation_errors = r.campaign.estimation_errors;
  // The threads left over when there are fewer cut tests than threads run estimator variants.
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = options.jobs > 0 ? options.jobs : hw;
  cut_options.jobs = std::max(1, threads / std::max(1, static_cast<int>(cuts.size())));
  parallel_for(cuts.size(), options.jobs, [&](std::size_t k) {
    run_cut(r.campaign.tests[cuts[k]], r.cut_inputs, cut_options, r.tests[cuts[k]]);
  });

  // Provenance: every file read, hashed.
  auto add_input = [&](const fs::path& p) {
    if (!fs::exists(p)) return;
    InputFile f;
    f.relative_path = fs::relative(p, r.campaign.root).generic_string();
    f.bytes = fs::file_size(p);
    f.sha256 = sha256_file(p);
    r.inputs.push_back(std::move(f));
  };
  add_input(r.campaign.root / "campaign.yaml");
  if (r.campaign.has_truth) add_input(r.campaign.truth_file);
  for (const auto& t : r.campaign.tests) {
    add_input(t.folder / "test.yaml");
    if (!t.data.file.empty()) add_input(t.data.file);
  }
  r.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace chatterlab::app
