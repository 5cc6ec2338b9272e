#pragma once
// Channels by name, as a scenario's `channel:` or `--channel` selects them, with the scenario's
// `channel_options` applied.
#include <memory>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"
#include "raytrace/trace_options.h"

namespace rfidray::cli {

// Names accepted by make_channel, in the order --help lists them.
std::vector<std::string> channel_names();
// The ray tracer's options with the scenario's channel_options applied (level not set).
TraceOptions trace_options(const ChannelOptionsSpec& spec);
// Builds the named channel for a scenario (ray-traced channels load scenario.scene; `auto` also samples the
// scenario's links and picks a level, raytrace/fidelity.h). Lines for the user about what was built (the
// auto choice and why) are appended to `report` when given. Throws InputError naming `field` for an unknown
// name.
std::unique_ptr<Channel> make_channel(const std::string& name, const Scenario& scenario,
                                      const std::string& field = "channel",
                                      std::vector<std::string>* report = nullptr);

}  // namespace rfidray::cli
