#pragma once
// Channels by name, as a scenario's `channel:` or `--channel` selects them.
#include <memory>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"

namespace rfidray::cli {

// Names accepted by make_channel, in the order --help lists them.
std::vector<std::string> channel_names();
// Builds the named channel for a scenario (ray-traced channels load scenario.scene). Throws InputError
// naming `field` for an unknown name.
std::unique_ptr<Channel> make_channel(const std::string& name, const Scenario& scenario,
                                      const std::string& field = "channel");

}  // namespace rfidray::cli
