#pragma once
// Channels by level, as a scenario's `channel:` or `--channel` selects them, with the scenario's
// `channel_options` applied. Throws InputError for unusable scenes; prints the scene's warnings to stderr.
#include <memory>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/channel_level.h"
#include "core/scenario.h"
#include "core/simulation.h"
#include "raytrace/scene.h"
#include "raytrace/trace_options.h"

namespace rfidray {

// The scene of a scenario (its meshes loaded, materials resolved), printing its warnings and notes to stderr as
// the factory does; for callers that need the scene itself as well (coverage maps draw its floor plan) and pass
// it to the make_channel overload below, so it is loaded once.
std::shared_ptr<const Scene> load_scenario_scene(const Scenario& scenario, ChannelLevel level);
// The ray tracer's options with the scenario's channel_options applied (level not set).
TraceOptions trace_options(const ChannelOptionsSpec& spec);
// Builds the channel of `level` for a scenario (traced levels load scenario.scene; kAuto also samples the
// scenario's links at the poses of `motion` and picks a level, raytrace/fidelity.h). Lines for the user about
// what was built (the auto choice and why) are appended to `report` when given.
std::unique_ptr<Channel> make_channel(ChannelLevel level, const Scenario& scenario, const SceneMotion& motion,
                                      std::vector<std::string>* report = nullptr);
// The same on a scene built elsewhere (e.g. from a Gazebo world); `scenario` supplies the channel options and,
// for kAuto, the antennas and tags whose links are sampled. scenario.scene is not read.
std::unique_ptr<Channel> make_channel(ChannelLevel level, const Scenario& scenario, const SceneMotion& motion,
                                      std::shared_ptr<const Scene> scene, std::vector<std::string>* report = nullptr);
// A fixed level (not kAuto, which needs a run's motion: throws InputError) on a given scene.
std::unique_ptr<Channel> make_channel(ChannelLevel level, const ChannelOptionsSpec& options,
                                      std::shared_ptr<const Scene> scene);
// For callers without a run's motion: builds it (kAuto needs it) and forwards.
std::unique_ptr<Channel> make_channel(ChannelLevel level, const Scenario& scenario,
                                      std::vector<std::string>* report = nullptr);

}  // namespace rfidray
