// Group product `lobes`: the campaign's stability lobe diagrams (issue 13, docs/lobes.md
// "Campaign section"). Whenever the campaign has modal parameters and cutting coefficients it
// draws, for each cut condition (operation, radial immersion) of its cut tests, the lobes of
// the hammer-test modes with the dynamometer coefficients and of each cut's identified set,
// with every cut test measured at that condition overlaid (stable or chatter, ramps with their
// bifurcation depth, an incline and a decline at one speed with their hysteresis band).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analysis/lobes/lobes.h"
#include "app/lobes/lobes_output.h"
#include "app/pipeline/kind.h"

namespace chatterlab::app {

// Automatic grid of the campaign diagrams (docs/lobes.md "Campaign section").
constexpr int kCampaignLobeSpeeds = 200;

struct LobeSource {
  std::string key;    // results.json key: "hammer-dyno" or "identified:<test id>"
  std::string label;  // legend
  std::string note;   // where its values come from
  lobes::LobesInput input;
  int steps_per_tooth = 0;
  lobes::LobesResult sd;
  std::optional<lobes::ZeroOrderResult> zoa;  // hammer-dyno only
  lobes::LobesResult at_measured;             // SD at the measured speeds (same order)
};

struct LobeDiagram {
  std::string slug;  // figure name part, e.g. "up-milling-0.382mm"
  milling::Operation operation = milling::Operation::kUpMilling;
  double radial_immersion_m = 0.0;
  double max_depth_m = 0.0;
  std::vector<double> measured_rpm;  // distinct speeds of the measured cuts, ascending
  std::vector<LobeSource> sources;
  std::vector<MeasuredPoint> measured;
  std::vector<Hysteresis> hysteresis;
  std::vector<std::string> notes;  // sources that could not be drawn, and why
};

struct LobesGroupResult : KindResult {
  std::vector<LobeDiagram> diagrams;
};

struct CutSummary;  // app/kinds/cut/cut_summary.h

// The measured cuts of one condition as points and segments (docs/lobes.md "Measured points"),
// the hysteresis band of each incline and decline at one speed (within 0.1 %), and the distinct
// measured speeds, into d.
void add_measured_points(const std::vector<const CutSummary*>& cuts, LobeDiagram& d);

class LobesGroup : public GroupProduct {
 public:
  std::string name() const override { return "lobes"; }
  // A tool in campaign.yaml, a tap test, and a dyno-slot or a cut test.
  bool applies(const CampaignSpec& c) const override;
  std::vector<Need> needs(const CampaignSpec&) const override;
  std::vector<std::string> provides(const CampaignSpec&) const override { return {}; }
  void run(const CampaignValues& in, const RunContext& ctx, GroupOutcome& out) const override;
  bool cacheable() const override { return true; }
  std::string save(const GroupOutcome& out) const override;
  void restore(const std::string& bytes, GroupOutcome& out) const override;
  nlohmann::json results(const GroupOutcome& out) const override;
  void figures(const CampaignResults&, const GroupOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r, const GroupOutcome& out,
                                const FigureSet& figures) const override;
};

}  // namespace chatterlab::app
