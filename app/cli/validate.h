// `chatterlab validate <campaign>`: every problem that would skip work in `report`, before
// computing anything.
#pragma once

#include <ostream>

#include "app/core/campaign.h"

namespace chatterlab::app {

// Prints the tests found and every problem (campaign errors, kinds' campaign.yaml blocks such
// as `estimation:`, per-test errors, records that do not hold a kind's channels or windows).
// Every kind of format version 1 is analysed; an unknown kind is an error naming the known
// ones. Returns 1 when anything would be skipped in a report, else 0.
int validate_campaign(CampaignSpec& c, std::ostream& out);

}  // namespace chatterlab::app
