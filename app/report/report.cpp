#include "app/report/report.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>
#include <vector>

#include "analysis/common/library_versions.h"
#include "app/cli/exit_codes.h"
#include "app/cli/progress.h"
#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/git_commit.h"
#include "app/report/document.h"
#include "app/report/figure_jobs.h"
#include "app/report/html_pages.h"
#include "app/report/results_json.h"
#include "app/report/results_table.h"
#include "app/report/truth.h"
#include "render/mustache_template.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

// The settings in force as rows "kind: a.b.c = value" (the same values as results.json
// `settings`, where they keep their types).
void flatten_settings(const std::string& prefix, const json& j, json& rows) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) {
      flatten_settings(prefix.empty() ? k : prefix + "." + k, v, rows);
    }
    return;
  }
  std::string value;
  if (j.is_number_float()) {
    value = fmt_sig(j.get<double>(), 6);
  } else if (j.is_string()) {
    value = j.get<std::string>();
  } else {
    value = j.dump(-1, ' ', false, json::error_handler_t::replace);
  }
  rows.push_back({{"key", prefix}, {"value", value}});
}

// Gives every object in `j` whose "id" names one of `ids` the key "anchor" (test_anchor of
// the id), so that the kinds' templates can mark each test's section with it.
void add_anchors(json& j, const std::map<std::string, std::string>& ids) {
  if (j.is_array()) {
    for (auto& e : j) add_anchors(e, ids);
    return;
  }
  if (!j.is_object()) return;
  if (const auto it = j.find("id"); it != j.end() && it->is_string()) {
    if (const auto a = ids.find(it->get<std::string>()); a != ids.end()) j["anchor"] = a->second;
  }
  for (auto& [k, v] : j.items()) {
    if (v.is_structured()) add_anchors(v, ids);
  }
}

// test_anchor of every test's id, made unique ("-2", "-3", ... after the first): ids such as
// "a/b" and "a-b" would share one.
std::map<std::string, std::string> unique_test_anchors(const CampaignResults& r) {
  std::map<std::string, std::string> anchors;
  std::set<std::string> used;
  for (const auto& t : r.tests) {
    if (anchors.count(t.spec->id) > 0) continue;
    const std::string base = test_anchor(t.spec->id);
    std::string a = base;
    for (int n = 2; used.count(a) > 0; ++n) a = base + "-" + std::to_string(n);
    used.insert(a);
    anchors[t.spec->id] = a;
  }
  return anchors;
}

// The kinds' sections in registry order, each rendered from templates/kinds/<name>.html with
// the context its kind gives, and the nested table of contents: each section's entries, the
// first with the tests whose sections carry their anchor as children. Returns the anchors of
// the tests that have a section, by test id.
std::map<std::string, std::string> kind_sections(const CampaignResults& r, const FigureSet& figures,
                                                 json& ctx, std::vector<std::string>& warnings) {
  const auto tdir = templates_dir();
  json sections = json::array(), toc = json::array();
  std::map<std::string, std::string> anchored;
  const std::map<std::string, std::string> unique = unique_test_anchors(r);
  const auto add = [&](const std::string& name, json section,
                       const std::vector<const TestOutcome*>& tests) {
    if (section.is_null()) return;
    std::map<std::string, std::string> ids;
    for (const TestOutcome* t : tests) ids[t->spec->id] = unique.at(t->spec->id);
    add_anchors(section, ids);
    const std::string html =
        render::render_template_file(tdir / "kinds" / (name + ".html"), section);
    sections.push_back({{"html", html}});
    json children = json::array();
    for (const TestOutcome* t : tests) {
      const std::string& anchor = ids[t->spec->id];
      if (html.find("id=\"" + anchor + "\"") == std::string::npos) continue;
      children.push_back({{"anchor", anchor}, {"title", t->spec->id.empty() ? "." : t->spec->id}});
      anchored[t->spec->id] = anchor;
    }
    bool first = true;
    for (json entry : section.value("toc", json::array())) {
      entry["children"] = first ? children : json::array();
      entry["has_children"] = first && !children.empty();
      toc.push_back(entry);
      first = false;
    }
  };
  for (const auto& entry : r.kinds->in_order()) {
    if (entry.kind) {
      std::vector<const TestOutcome*> ok;
      for (const auto& t : r.tests) {
        if (t.status.ok() && t.spec->kind == entry.kind->name()) ok.push_back(&t);
      }
      const json section = entry.kind->report_section(r, ok, figures);
      // A kind without a section of its own: its tests' warnings go to the campaign's list.
      if (section.is_null()) {
        for (const TestOutcome* t : ok) {
          for (const auto& w : t->warnings) {
            warnings.push_back((t->spec->id.empty() ? "." : t->spec->id) + ": " + w);
          }
        }
      }
      add(entry.kind->name(), section, ok);
    } else if (const GroupOutcome* g = r.group(entry.group->name())) {
      for (const auto& w : g->status.warnings) {
        warnings.push_back(g->name + " group: " + w);
      }
      // A group's section may show tests of its own (the dynamometer slot cuts' table):
      // those not shown elsewhere can take their anchor there.
      std::vector<const TestOutcome*> rest;
      for (const auto& t : r.tests) {
        if (t.status.ok() && anchored.count(t.spec->id) == 0) rest.push_back(&t);
      }
      add(entry.group->name(), entry.group->report_section(r, *g, figures), rest);
    }
  }
  ctx["sections"] = sections;
  ctx["toc"] = toc;
  return anchored;
}

FigureSet draw_figures(const CampaignResults& r, const std::filesystem::path& out, int jobs) {
  FigureJobs work;
  for (const auto& t : r.tests) {
    if (!t.status.ok()) continue;
    if (const TestKind* kind = r.kinds->find(t.spec->kind)) kind->figures(r, t, work);
  }
  for (const auto& g : r.groups) {
    if (const GroupProduct* p = r.kinds->find_group(g.name)) p->figures(r, g, work);
  }
  return work.draw(out, jobs);
}

}  // namespace

// The campaign folder's own name ("demo" for /any/where/demo/): the report shows no path of
// the machine it ran on.
std::string campaign_folder_name(const CampaignSpec& c) {
  std::error_code ec;
  std::filesystem::path root =
      std::filesystem::weakly_canonical(std::filesystem::absolute(c.root, ec), ec);
  if (root.filename().empty()) root = root.parent_path();
  return root.filename().string();
}

// results.json `campaign` matches [A-Za-z0-9._-]+ (docs/results.schema.json): campaign.yaml
// `name` when it is set and valid, else the campaign folder's name with every other character
// as '-' ("campaign" when nothing is left).
std::string results_campaign_name(const CampaignSpec& c) {
  const auto valid_char = [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' || ch == '-';
  };
  if (!c.name.empty() && std::all_of(c.name.begin(), c.name.end(), valid_char)) return c.name;
  std::string name = campaign_folder_name(c);
  for (char& ch : name) {
    if (!valid_char(ch)) ch = '-';
  }
  if (name.empty() || name == "." || name == "..") name = "campaign";
  return name;
}

int run_report(const std::filesystem::path& campaign_dir, const std::filesystem::path& out,
               const ReportOptions& options, std::ostream& log, const KindRegistry& kinds) {
  const auto t0 = std::chrono::steady_clock::now();
  std::ostream& err = options.errors != nullptr ? *options.errors : log;
  CampaignSpec spec = load_campaign(campaign_dir, kinds);
  if (!spec.campaign_yaml_found) {
    for (const auto& e : spec.errors) err << "chatterlab report: " << e << "\n";
    return kExitInputError;
  }
  PipelineOptions popt;
  popt.jobs = options.jobs;
  popt.cache = options.cache;
  if (options.progress) {
    log << "report: " << spec.tests.size() << " tests found in " << results_campaign_name(spec)
        << std::endl;
    const double after = options.estimate_after_s;
    popt.on_finished = [&log, after](const NodeFinished& f) {
      log << progress_line(f, after) << std::endl;  // flushed: a line as each one finishes
    };
  }
  CampaignResults r = run_campaign(std::move(spec), popt, kinds);
  r.options.on_finished = nullptr;  // `log` is not for later users of r
  r.options.cache = nullptr;        // nor is the cache
  const TruthComparison truth = compare_with_truth(r);

  if (options.before_writing) options.before_writing();
  std::filesystem::create_directories(out / "figures");
  const auto t_figures = std::chrono::steady_clock::now();
  const FigureSet figures = draw_figures(r, out, options.jobs);
  if (options.progress) {
    log << "report: figures drawn in "
        << format_duration(
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t_figures).count())
        << std::endl;
  }
  // Files the tests write beside results.json, which names them.
  std::vector<std::string> file_errors;
  for (const auto& t : r.tests) {
    const TestKind* kind = r.kinds->find(t.spec->kind);
    if (!t.status.ok() || kind == nullptr) continue;
    try {
      kind->write_files(t, out);
    } catch (const WriteError&) {
      throw;  // the output, not the test: the run fails and the previous report stays
    } catch (const std::filesystem::filesystem_error& e) {  // its folder could not be made
      throw WriteError("cannot write " + e.path1().string() + ": " + e.code().message());
    } catch (const std::exception& e) {
      file_errors.push_back(t.spec->id + ": " + e.what());
    }
  }

  json ctx;
  const auto& c = r.campaign;
  ctx["campaign"] = {{"name", c.name.empty() ? results_campaign_name(c) : c.name},
                     {"description", c.description},
                     {"workpiece", c.workpiece},
                     {"machine", c.machine},
                     {"folder", campaign_folder_name(c)}};
  if (c.tool) {
    json tool = {{"teeth", c.tool->teeth}, {"radius_mm", fmt_sig(c.tool->radius_m * 1e3, 4)}};
    if (c.tool->helix_deg) tool["helix_deg"] = fmt_sig(*c.tool->helix_deg, 3);
    ctx["campaign"]["tool"] = tool;
  }
  ctx["generated_utc"] = utc_timestamp();
  ctx["generated_iso"] = utc_timestamp_iso();
  ctx["version"] = CHATTERLAB_VERSION;
  json skipped = json::array(), internal = json::array();
  std::vector<std::string> warnings = c.errors;
  warnings.insert(warnings.end(), c.warnings.begin(), c.warnings.end());
  for (const auto& [block, errors] : c.block_errors) {
    for (const auto& e : errors) warnings.push_back(e);
  }
  warnings.insert(warnings.end(), truth.warnings.begin(), truth.warnings.end());
  warnings.insert(warnings.end(), figures.errors.begin(), figures.errors.end());
  warnings.insert(warnings.end(), file_errors.begin(), file_errors.end());
  int ok = 0;
  const std::map<std::string, std::string> anchors = kind_sections(r, figures, ctx, warnings);
  json tests = json::array();
  for (const auto& t : r.tests) {
    const std::string id = t.spec->id.empty() ? "." : t.spec->id;
    const TestKind* kind = r.kinds->find(t.spec->kind);
    const auto anchor = anchors.find(t.spec->id);
    tests.push_back({{"id", id},
                     {"anchor", anchor != anchors.end() ? json(anchor->second) : json()},
                     {"kind", t.spec->kind.empty() ? "?" : t.spec->kind},
                     {"status", status_word(t.status, t.failure)},
                     {"note", t.status.ok() && kind ? kind->note(t) : std::string()}});
    if (t.status.ok()) {
      ++ok;
    } else {
      (t.failure == Failure::kInternal ? internal : skipped)
          .push_back({{"id", id}, {"reason", t.status.message}});
    }
  }
  for (const auto& g : r.groups) {
    if (g.failure == Failure::kInternal) {
      internal.push_back({{"id", "group " + g.name}, {"reason", g.status.message}});
    }
  }
  ctx["tests"] = tests;
  ctx["skipped"] = skipped;
  ctx["summary"] = {{"tests_found", r.tests.size()},
                    {"tests_ok", ok},
                    {"tests_skipped", r.tests.size() - static_cast<std::size_t>(ok)}};
  ctx["has_skipped"] = !skipped.empty();
  ctx["has_internal_errors"] = !internal.empty();
  ctx["internal_errors"] = internal;
  ctx["has_warnings"] = !warnings.empty();
  ctx["warnings"] = warnings;
  json truth_rows = json::array();
  for (const auto& row : truth.rows) {
    truth_rows.push_back({{"quantity", row.quantity},
                          {"source", row.source},
                          {"truth", fmt_sig(row.truth, 5)},
                          {"estimate", fmt_sig(row.estimate, 5)},
                          {"error_pct", fmt_fixed(row.error_pct, 2)}});
  }
  ctx["truth"] = {{"present", truth.present && !truth.rows.empty()}, {"rows", truth_rows}};
  if (truth.present && !truth.rows.empty()) {
    ctx["toc"].push_back({{"anchor", "truth"}, {"title", "Comparison with known values"}});
  }
  ctx["toc"].push_back({{"anchor", "provenance"}, {"title", "Provenance"}});
  ctx["toc"].push_back({{"anchor", "references"}, {"title", "References"}});
  json inputs = json::array();
  for (const auto& f : r.inputs) {
    inputs.push_back({{"file", f.relative_path}, {"bytes", f.bytes}, {"sha256", f.sha256}});
  }
  json settings = json::array();
  flatten_settings("", settings_json(r), settings);
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  settings.push_back(
      {{"key", "worker threads"},
       {"value", options.jobs > 0 ? std::to_string(options.jobs)
                                  : "one per hardware thread (" + std::to_string(hw) + ")"}});
  const LibraryVersions lib = library_versions();
  const double runtime =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ctx["provenance"] = {{"inputs", inputs},
                       {"runtime_s", fmt_sig(runtime, 3)},
                       {"settings", settings},
                       {"git_commit", CHATTERLAB_GIT_COMMIT},
                       {"libraries", json::array({{{"name", "Eigen"}, {"version", lib.eigen}},
                                                  {{"name", "Ceres"}, {"version", lib.ceres}},
                                                  {{"name", "FFTW"}, {"version", lib.fftw}}})}};

  // results.json first: it must exist even if the PDF step fails.
  {
    json results = results_json(r, truth, figures);
    results["campaign"] = results_campaign_name(c);
    results["results_csv"] = "results.csv";
    // Checked: a failed write throws, naming the file, and nothing says it was written.
    // Names from the file system or a data file that are not UTF-8 reach results.json with
    // U+FFFD in place of each bad byte (a throw here would lose the whole report).
    write_file_checked(out / "results.json",
                       results.dump(2, ' ', false, json::error_handler_t::replace) + "\n");
    write_file_checked(out / "results.csv", results_table_csv(results));
  }
  if (options.progress && options.pdf) log << "report: writing report.pdf" << std::endl;
  const bool pdf_written = write_documents(
      "report.html", ctx, out, DocumentOptions{options.pdf, options.single_file}, "report", err);
  const int internal_errors = r.internal_errors();
  int rc = options.pdf && !pdf_written ? kExitInputError : kExitOk;
  if (ok == 0) rc = kExitNothingAnalysed;
  if (internal_errors > 0) rc = kExitInternalError;
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "report: " << r.tests.size() << " tests, " << ok << " analysed, "
      << r.tests.size() - static_cast<std::size_t>(ok) << " skipped; wrote "
      << (out / "index.html").string() << (pdf_written ? ", report.pdf" : "")
      << ", results.json in " << fmt_sig(total, 3) << " s\n";
  for (const auto& s : skipped)
    log << "  skipped " << s["id"].get<std::string>() << ": " << s["reason"].get<std::string>()
        << "\n";
  for (const auto& s : internal)
    err << "chatterlab report: INTERNAL ERROR " << s["id"].get<std::string>() << ": "
        << s["reason"].get<std::string>() << "\n";
  if (ok == 0) {
    err << "chatterlab report: no test was analysed ("
        << (r.tests.empty()
                ? std::string("no test.yaml found below the campaign folder")
                : "every one of the " + std::to_string(r.tests.size()) + " tests was skipped" +
                      (internal_errors > 0 ? " or stopped on an internal error" : ""))
        << "); exit status " << rc << "\n";
  }
  return rc;
}

}  // namespace chatterlab::app
