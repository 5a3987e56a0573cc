// `chatterlab validate`: every problem of a campaign, before anything is computed.
#pragma once

#include <ostream>

#include "app/campaign.h"

namespace chatterlab::app {

// Channels a test kind reads from its signal file.
std::vector<std::string> required_channels(const TestSpec& t);

// Opens the test's signal file and checks the channels its kind needs; problems are
// appended to t.errors (the test becomes unusable). Does nothing for an already unusable test.
void check_signals(TestSpec& t);

// Prints the tests found and every problem; returns the process exit code (0: all usable).
int validate_campaign(CampaignSpec& c, std::ostream& out);

}  // namespace chatterlab::app
