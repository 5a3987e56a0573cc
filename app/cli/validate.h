// `chatterlab validate <campaign>`: every problem that would skip work in `report`, before
// computing anything.
#pragma once

#include <ostream>

#include "app/core/campaign.h"

namespace chatterlab::app {

// Prints the tests found and every problem (campaign errors, kinds' campaign.yaml blocks such
// as `estimation:`, per-test errors, records that do not hold a kind's channels or windows).
// A test of a kind the format defines but this version does not analyse (dyno-frf,
// force-record, frf, sweep-frf, spindle-current) is listed as "not analysed by this version"
// and is no problem when nothing else is wrong with it. Returns 1 when anything else would be
// skipped in a report, else 0.
int validate_campaign(CampaignSpec& c, std::ostream& out);

}  // namespace chatterlab::app
