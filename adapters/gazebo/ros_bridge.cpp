#include "adapters/gazebo/ros_bridge.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <set>
#include <stdexcept>
#include <thread>

#include "adapters/gazebo/live_world.h"
#include "adapters/gazebo/tick_csv.h"
#include "adapters/ros/pose_input.h"
#include "adapters/ros/ros_session.h"
#include "adapters/ros/tag_array_publisher.h"
#include "core/error.h"
#include "core/reader_model.h"
#include "core/number_text.h"

namespace rfidray::gazebo {
namespace {

Pose from_value(const ros_bridge::PoseValue& v, const std::string& what) {
  for (double x : {v.x, v.y, v.z, v.qx, v.qy, v.qz, v.qw})
    if (!std::isfinite(x)) throw InputError(what + ": pose is not finite");
  const Quat q(v.qw, v.qx, v.qy, v.qz);
  if (!(q.norm() > 0.0)) throw InputError(what + ": orientation quaternion is zero");
  return Pose{Vec3(v.x, v.y, v.z), q.normalized()};
}

ros_bridge::PoseValue to_value(const Pose& p) {
  return {p.position.x(), p.position.y(), p.position.z(), p.orientation.x(), p.orientation.y(), p.orientation.z(),
          p.orientation.w()};
}

// ROS errors (no master, ...) are the user's setup: exit 2 with the message.
template <class F>
auto ros_call(const std::string& what, F&& f) {
  try {
    return f();
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    throw InputError(what + ": " + e.what());
  }
}

}  // namespace

RosParams ros_private_params(const std::string& node_name, const std::vector<std::string>& ros_args) {
  return ros_call("ROS", [&] {
    const auto session = ros_bridge::RosSession::get(node_name, ros_args);
    return RosParams{session->private_params(), session};
  });
}

int run_ros_bridge(const RosBridgeOptions& o) {
  auto say = [&](const std::string& s) {
    if (!o.quiet) std::fprintf(stderr, "rfidray gazebo: %s\n", s.c_str());
  };
  GazeboWorld world = load_bridge_world(o.world, o.model);
  if (o.node_name.empty() || o.node_name == "gazebo" || o.node_name == "/gazebo")
    throw InputError("option --ros-node: '" + o.node_name + "' would replace Gazebo's own ROS node; pick another "
                     "name (default rfidray)");
  if (o.world_frame.empty()) throw InputError("option --world-frame: must not be empty");

  // Antenna → TF frame: the command line / parameters first, then the SDF's <frame>.
  std::vector<std::string> frame_of(world.scenario.antennas.size());
  std::string antenna_names;
  for (size_t a = 0; a < world.scenario.antennas.size(); ++a) {
    frame_of[a] = world.antenna_mounts[a].frame;
    antenna_names += (a ? ", " : "") + world.scenario.antennas[a].reader.name;
  }
  for (const auto& [antenna, frame] : o.frames) {
    size_t a = 0;
    while (a < frame_of.size() && world.scenario.antennas[a].reader.name != antenna) ++a;
    if (a == frame_of.size())
      throw InputError("option --frame: no antenna '" + antenna + "' in " + o.world.file + " (antennas: " +
                       antenna_names + ")");
    if (frame.empty()) throw InputError("option --frame: empty TF frame for antenna '" + antenna + "'");
    frame_of[a] = frame;
  }
  // model_states names → the world's top-level models.
  std::map<std::string, size_t> top_models;
  for (size_t e = 0; e < world.entities.size(); ++e)
    if (world.entities[e].parent < 0 && world.entities[e].kind == Entity::Kind::kModel) top_models[world.entities[e].name] = e;
  const std::set<std::string> ignored(o.ignore_models.begin(), o.ignore_models.end());
  const std::string world_name = world.name, world_file = o.world.file;

  LiveOptions live_options;
  live_options.seed = o.seed;
  live_options.channel = o.channel;
  live_options.duration_s = o.duration_s;
  LiveWorld live(std::move(world), live_options);
  const Scenario& scenario = live.scenario();

  TickCsv csv(o.csv_dir, scenario);

  // ROS: the session first (its node name), then outputs, then inputs.
  std::vector<std::string> names;
  for (const AntennaSpec& a : scenario.antennas) names.push_back(a.reader.name);
  const auto session = ros_call("ROS", [&] { return ros_bridge::RosSession::get(o.node_name, o.ros_args); });
  const bool sim_time = o.use_sim_time.value_or(session->use_sim_time());
  ros_bridge::TagArrayPublisher publisher(o.node_name, names, o.topic_namespace, o.world_frame);
  ros_bridge::PoseInputOptions input_options;
  input_options.node_name = o.node_name;
  input_options.model_states_topic = o.model_states_topic;
  input_options.use_sim_time = sim_time;
  auto input = ros_call("ROS pose input", [&] { return std::make_unique<ros_bridge::PoseInput>(input_options); });
  say("world '" + world_name + "' from " + world_file + "; ROS node " + session->node_name() + " at " +
      session->master_uri() + "; time from " + (sim_time ? "/clock (use_sim_time)" : "/tf stamps"));
  say("inputs: " + input->topics() + "; TagArray on " + publisher.topics() + " (frame '" + o.world_frame + "')");
  for (size_t a = 0; a < frame_of.size(); ++a)
    say("antenna '" + names[a] + "': " + (frame_of[a].empty() ? "follows its model in /gazebo/model_states"
                                                               : "TF " + o.world_frame + " -> " + frame_of[a]));

  // An antenna with a TF frame: the chain at the tick time, waiting (bounded) for the transforms to arrive.
  live.set_antenna_pose_provider([&](size_t a, double t_s) -> std::optional<Pose> {
    if (frame_of[a].empty()) return std::nullopt;
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.tf_timeout_s);
    ros_bridge::PoseValue v;
    std::string error;
    while (!input->lookup(o.world_frame, frame_of[a], t_s, v, error)) {
      if (stop_requested() || std::chrono::steady_clock::now() >= until)
        throw InputError("TF: no transform " + o.world_frame + " -> " + frame_of[a] + " (antenna '" + names[a] +
                         "') at t = " + num(t_s) + " s within " + num(o.tf_timeout_s) + " s (--tf-timeout): " +
                         error + " [frames known: " + input->frames() + "]");
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const std::string what = "TF " + o.world_frame + " -> " + frame_of[a] + " at t = " + num(t_s) + " s";
    return from_value(v, what).compose(live.world().antenna_mounts[a].pose);
  });

  auto sink = [&](const TickReadings& t) {
    csv.write(scenario, t);
    std::vector<ros_bridge::TagValue> tags;
    for (const ReadRecord& r : t.reads)
      tags.push_back({scenario.tags[r.tag].tag.name, r.distance_m, r.reading.phase_rad, r.reading.rssi_dbm});
    publisher.publish(t.antenna, t.time_s, to_value(t.antenna_pose), tags);
  };

  // The first TagArray is lost unless its subscribers are known: wait for them, bounded.
  if (o.connect_timeout_s > 0.0) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.connect_timeout_s);
    while (!publisher.all_connected() && !stop_requested() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!publisher.all_connected()) say("no subscriber on some TagArray topics after --connect-timeout; publishing anyway");
  }
  install_stop_handlers();

  uint64_t model_messages = 0, restarts = 0;
  auto last_message = std::chrono::steady_clock::now();
  ros_bridge::InputEvent event;
  while (!stop_requested() && !live.finished()) {
    if (!input->pop(event, 0.1)) {
      const double idle = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_message).count();
      if (idle > o.idle_timeout_s) {
        say("no input message for " + num(o.idle_timeout_s) + " s; stopping");
        break;
      }
      continue;
    }
    last_message = std::chrono::steady_clock::now();
    bool restarted = false;
    live.advance(event.time_s, sink, &restarted);
    if (restarted) {
      ++restarts;
      say("simulation time went back to " + num(event.time_s) + " s (a reset): ticks start again from there");
    }
    if (event.kind != ros_bridge::InputEvent::Kind::kModelStates) continue;
    ++model_messages;
    for (const ros_bridge::NamedPose& m : event.models) {
      const auto it = top_models.find(m.name);
      if (it == top_models.end()) {
        if (ignored.count(m.name)) continue;
        std::string known;
        for (const auto& [name, e] : top_models) known += (known.empty() ? "" : ", ") + name;
        throw InputError(o.model_states_topic + ": model '" + m.name + "' is not in world '" + world_name + "' (" +
                         world_file + "; its models: " + known + "). Run the bridge on the world Gazebo runs, or "
                         "pass --ignore-model " + m.name + " if it carries nothing the radio sees");
      }
      live.set_entity_pose(it->second, from_value(m.pose, o.model_states_topic + ": model '" + m.name + "'"));
    }
  }
  say(std::to_string(live.ticks()) + " antenna ticks from " + std::to_string(input->messages()) + " ROS messages (" +
      std::to_string(model_messages) + " model_states), " + std::to_string(restarts) + " resets, " +
      std::to_string(live.scene_builds()) + " scene builds, simulation time " + num(live.time_s()) + " s");
  return 0;
}

}  // namespace rfidray::gazebo
