// The report's figures, drawn through render/ (gnuplot backend) in parallel.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "app/pipeline.h"
#include "app/truth.h"
#include "render/figure.h"

namespace chatterlab::app {

struct FigureSet {
  std::map<std::string, std::string> tap;  // test id -> stem relative to the report folder
                                           // (stem.svg on screen, stem.png in print)
  std::string dyno;                        // stem, empty when not drawn
  // Cut tests: id -> figure kind (processing, offset, bifurcation, poincare, chip,
  // estimator:<variant>, e.g. estimator:ekf-modal-x) -> stem.
  std::map<std::string, std::map<std::string, std::string>> cut;
  std::vector<std::string> errors;  // figures that could not be drawn
  std::string of(const std::string& id) const {
    const auto it = tap.find(id);
    return it == tap.end() ? std::string() : it->second;
  }
};

// Figure models (exposed for tests).
render::Figure tap_frf_figure(const TestOutcome& t);
render::Figure dyno_force_figure(const CampaignResults& r);
render::Figure cut_processing_figure(const CutOutcome& c);
render::Figure cut_offset_figure(const sync::OffsetAngleResult& o);
// Percent error of a variant's estimates against time, one panel per estimate key: the run
// and its seeded repeatability runs (000 figs 6.1-6.17, 6.19-6.20). A key without a reference
// is shown as the difference from the run's own final value.
render::Figure estimator_error_figure(const VariantOutcome& v,
                                      const std::map<std::string, ReferenceValue>& reference);
// Chip thickness of every tooth at the start of the filter window (000 fig. 6.18).
render::Figure chip_thickness_figure(const CutEstimation& e);

FigureSet render_report_figures(const CampaignResults& r, const std::filesystem::path& out,
                                int jobs);

}  // namespace chatterlab::app
