// `rfidray gazebo`: the live bridge to a running Gazebo (adapters/gazebo/bridge.h). Built only with the bridge;
// without it cli/commands.cpp registers a subcommand that says what is missing.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <memory>
#include <optional>

#include "adapters/gazebo/bridge.h"
#include "adapters/gazebo/ros_bridge.h"
#include "cli/adapters_plugin.h"
#include "cli/commands.h"
#include "core/error.h"

namespace rfidray::cli {
namespace {

struct GazeboOptions {
  io::WorldSourceOptions world;
  std::string input = "ign";
  std::string world_name, channel = "ideal", model, csv_dir, topic_prefix = "/rfid";
  std::optional<std::string> ros_node;  // default: "gazebo" (ign input, the seed's node), "rfidray" (ROS input)
  std::string partition, ip;
  uint64_t seed = 1;
  bool ros = false, quiet = false;
  std::optional<double> duration_s, idle_timeout_s;
  double scene_timeout_s = 10.0, connect_timeout_s = 2.0;
  // --input ros
  std::string topic_namespace = "/gazebo", world_frame = "world", model_states_topic = "/gazebo/model_states";
  std::vector<std::string> frames, ignore_models, ros_args;
  bool sim_time = false, no_sim_time = false;  // neither: the /use_sim_time parameter
  double tf_timeout_s = 5.0;
};

// The options a launch file may set as private ROS parameters (~name), by option name; the command line wins.
// Lists (resource_path, frame, ignore_model) take a YAML list, dictionaries (frame) {antenna: frame}.
const char* const kRosParams[] = {"world", "resource_path", "materials", "seed", "channel", "model", "csv",
                                  "duration", "idle_timeout", "connect_timeout", "tf_timeout", "world_frame",
                                  "frame", "ignore_model", "topic_namespace", "model_states_topic", "sim_time",
                                  "quiet"};

void add_options(CLI::App& cmd, GazeboOptions& o) {
  cmd.add_option("--input", o.input, "Pose input: ign (ign-transport, Gazebo Fortress) | ros (ROS 1, Gazebo 11)")
      ->capture_default_str()->check(CLI::IsMember({"ign", "ros"}));
  add_world_options(cmd, o.world);
  cmd.add_option("--world-name", o.world_name, "Gazebo world name in topic names (default: the SDF's <world name>)");
  cmd.add_option("--seed", o.seed, "Random seed, >= 0")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd.add_option("--channel", o.channel, "ideal | los | los+blocked | single-bounce")->capture_default_str();
  cmd.add_option("--model", o.model, "Reader model of every antenna (paper | physical); default: the world's")
      ->check(CLI::IsMember({"paper", "physical"}));
  cmd.add_option("--csv", o.csv_dir, "Also write <antenna>.csv readings in this directory");
  cmd.add_option("--topic-prefix", o.topic_prefix, "Prefix of the ign-transport topics")->capture_default_str();
  cmd.add_flag("--ros", o.ros, "Also publish rfid_sensor/TagArray on ROS 1 (needs a running roscore, ROS_MASTER_URI)");
  cmd.add_option("--ros-node", o.ros_node,
                 "ROS node name (default gazebo with --ros: topics /gazebo/<antenna>/data; rfidray with --input ros)");
  cmd.add_option("--partition", o.partition, "ign-transport partition (overrides IGN_PARTITION)");
  cmd.add_option("--ip", o.ip, "IGN_IP: the address ign-transport discovery uses (e.g. 127.0.0.1)");
  cmd.add_option("--duration", o.duration_s, "Stop after this much simulation time (s)")->check(CLI::NonNegativeNumber);
  cmd.add_option("--idle-timeout", o.idle_timeout_s, "Stop after this many wall seconds without pose messages")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--scene-timeout", o.scene_timeout_s, "Wait this long (s) for the scene/info service")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd.add_option("--connect-timeout", o.connect_timeout_s,
                  "Before the first tick, wait up to this long (s) for readings subscribers")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd.add_flag("-q,--quiet", o.quiet, "Print only warnings and errors");
  cmd.add_option("--frame", o.frames, "--input ros: antenna ANTENNA is at TF frame FRAME (ANTENNA=FRAME, repeatable)");
  cmd.add_option("--world-frame", o.world_frame, "--input ros: TF frame of Gazebo's world")->capture_default_str();
  cmd.add_option("--ignore-model", o.ignore_models, "--input ros: a model_states name that is not in the world (repeatable)");
  cmd.add_option("--topic-namespace", o.topic_namespace, "--input ros: TagArray on <namespace>/<antenna>/data")
      ->capture_default_str();
  cmd.add_option("--model-states-topic", o.model_states_topic, "--input ros: gazebo_msgs/ModelStates topic")
      ->capture_default_str();
  // Two flags, not one optional: CLI11 sets an optional flag to false when it is absent.
  cmd.add_flag("--sim-time", o.sim_time, "--input ros: time from /clock (default: the /use_sim_time parameter)");
  cmd.add_flag("--no-sim-time", o.no_sim_time, "--input ros: time from the /tf stamps, whatever /use_sim_time says");
  // roslaunch appends __name:=NODE __log:=FILE (and remappings) to a node's command line.
  cmd.add_option("ros-args", o.ros_args, "--input ros: ROS arguments NAME:=VALUE, as roslaunch passes them")
      ->check([](const std::string& a) {
        return a.find(":=") == std::string::npos ? "'" + a + "' is not a ROS argument NAME:=VALUE" : std::string();
      });
  cmd.add_option("--tf-timeout", o.tf_timeout_s, "--input ros: wait this long (wall s) for an antenna's TF chain")
      ->capture_default_str()->check(CLI::PositiveNumber);
}

int run_ros_input(CLI::App& cmd, GazeboOptions& o, void (*add_options)(CLI::App&, GazeboOptions&)) {
  const std::string node = o.ros_node.value_or("rfidray");
  gazebo::RosParams params = adapters_plugin().ros_private_params(node, o.ros_args);
  // Parameters become arguments of a second parse into the same options, for the options not given here.
  std::vector<std::string> args;
  for (const auto& [key, value] : params.values) {
    if (std::find(std::begin(kRosParams), std::end(kRosParams), key) == std::end(kRosParams))
      throw InputError("ROS parameter ~" + key + " of node " + node + ": not an option of rfidray gazebo --input ros");
    std::string opt = "--" + key;
    for (char& c : opt) c = c == '_' ? '-' : c;
    if (cmd.count(opt) > 0 || (key == "sim_time" && cmd.count("--no-sim-time") > 0)) continue;
    if (key == "quiet" || key == "sim_time") {
      if (value == "true") args.push_back(opt);
      else if (key == "sim_time" && value == "false") args.push_back("--no-sim-time");
      else if (value != "false")
        throw InputError("ROS parameter ~" + key + " of node " + node + ": true or false (got '" + value + "')");
      continue;
    }
    const bool list = key == "resource_path" || key == "frame" || key == "ignore_model";
    if (list && value.empty()) continue;  // an empty list or dictionary
    size_t begin = 0;
    do {
      const size_t end = list ? value.find(',', begin) : std::string::npos;
      args.push_back(opt);
      args.push_back(value.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
      begin = end == std::string::npos ? end : end + 1;
    } while (begin != std::string::npos);
  }
  if (!args.empty()) {
    CLI::App from_params("ROS parameters");
    add_options(from_params, o);
    std::reverse(args.begin(), args.end());  // CLI11 takes the arguments last first
    try {
      from_params.parse(args);
    } catch (const CLI::ParseError& e) {
      throw InputError("ROS parameters of node " + node + ": " + e.what());
    }
  }
  if (o.world.file.empty())
    throw InputError("option --world (or ROS parameter ~world): required (the world file Gazebo is running)");
  gazebo::RosBridgeOptions b;
  b.world.file = o.world.file;
  b.world.resource_path = o.world.resource_path;
  b.world.materials_file = o.world.materials_file;
  b.seed = o.seed;
  b.channel = parse_channel_level(o.channel, "--channel");
  b.model = o.model;
  b.csv_dir = o.csv_dir;
  b.node_name = node;
  b.ros_args = o.ros_args;
  b.topic_namespace = o.topic_namespace;
  b.world_frame = o.world_frame;
  for (const std::string& f : o.frames) {
    const size_t eq = f.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == f.size())
      throw InputError("option --frame: ANTENNA=TF_FRAME (got '" + f + "')");
    b.frames[f.substr(0, eq)] = f.substr(eq + 1);
  }
  b.ignore_models = o.ignore_models;
  b.model_states_topic = o.model_states_topic;
  if (o.sim_time && o.no_sim_time) throw InputError("options --sim-time and --no-sim-time: give one");
  if (o.sim_time || o.no_sim_time) b.use_sim_time = o.sim_time;
  if (o.duration_s) b.duration_s = *o.duration_s;
  if (o.idle_timeout_s) b.idle_timeout_s = *o.idle_timeout_s;
  b.tf_timeout_s = o.tf_timeout_s;
  b.connect_timeout_s = o.connect_timeout_s;
  b.quiet = o.quiet;
  const int rc = adapters_plugin().run_ros_bridge(b);
  params.session.reset();
  return rc;
}

int run_gazebo(const GazeboOptions& o) {
  if (o.world.file.empty()) throw InputError("option --world: required (the SDF world Gazebo is running)");
  if (!o.ros_args.empty())
    throw InputError("'" + o.ros_args[0] + "': ROS arguments (NAME:=VALUE) are read with --input ros only");
  gazebo::BridgeOptions b;
  b.world.file = o.world.file;
  b.world.resource_path = o.world.resource_path;
  b.world.materials_file = o.world.materials_file;
  b.world_name = o.world_name;
  b.seed = o.seed;
  b.channel = parse_channel_level(o.channel, "--channel");
  b.model = o.model;
  b.csv_dir = o.csv_dir;
  b.topic_prefix = o.topic_prefix;
  b.ros = o.ros;
  b.ros_node = o.ros_node.value_or("gazebo");
  b.partition = o.partition;
  b.ip = o.ip;
  if (o.duration_s) b.duration_s = *o.duration_s;
  if (o.idle_timeout_s) b.idle_timeout_s = *o.idle_timeout_s;
  b.scene_timeout_s = o.scene_timeout_s;
  b.connect_timeout_s = o.connect_timeout_s;
  b.quiet = o.quiet;
  return adapters_plugin().run_bridge(b);
}

}  // namespace

std::function<int()> setup_gazebo(CLI::App& app) {
  auto o = std::make_shared<GazeboOptions>();
  CLI::App* cmd = app.add_subcommand("gazebo", "Live bridge: follow a running Gazebo (ign-transport, or ROS 1), publish readings");
  cmd->footer(
      "Loads the SDF world Gazebo runs (--world, as for simulate --world) and follows it:\n"
      "  --input ign (default): asks /world/<name>/scene/info for the entity tree, follows\n"
      "    /world/<name>/pose/info and /world/<name>/dynamic_pose/info (ignition.msgs.Pose_V, poses relative to\n"
      "    the parent entity) and moves antennas, tags and obstacles.\n"
      "  --input ros (Gazebo 11 + gazebo_ros, ROS Noetic): /gazebo/model_states moves the world's models;\n"
      "    an antenna with a TF frame (--frame ANTENNA=FRAME, or <frame> in its sensor block) is at\n"
      "    --world-frame -> FRAME from /tf, /tf_static at the tick time; time from /clock (use_sim_time) or\n"
      "    the /tf stamps. Every option may come as a private ROS parameter (~seed, ~frame: {reader: mast})\n"
      "    from a launch file (adapters/ros/launch/rfidray_bridge.launch); the command line wins.\n"
      "Each antenna reads at its update rate in simulation time (tick k at k / rate, the poses stamped at or\n"
      "before it), with the same reader model and random streams as `rfidray simulate`: the same poses and\n"
      "--seed give the same readings. Publishes per antenna tick:\n"
      "  ign-transport  <prefix>/<antenna>/readings  rfidray.msgs.TagReadings; <prefix>/status BridgeStatus\n"
      "  ROS 1 (--ros)  /<ros-node>/<antenna>/data   rfid_sensor/TagArray, as the seed plugin (~/<antenna>/data)\n"
      "  ROS 1 (--input ros)  <topic-namespace>/<antenna>/data (default /gazebo/<antenna>/data, the seed's)\n"
      "  CSV (--csv D)  D/<antenna>.csv              the columns of `rfidray simulate`\n"
      "Discovery (ign): peers must share the ign-transport partition (--partition, else IGN_PARTITION, else\n"
      "GZ_PARTITION, else hostname:username) and reach each other on IGN_IP (--ip; 127.0.0.1 on one machine).\n"
      "Stops after --duration s of simulation time, --idle-timeout s without input, or on SIGINT/SIGTERM.");
  add_options(*cmd, *o);
  return [o, cmd] { return o->input == "ros" ? run_ros_input(*cmd, *o, &add_options) : run_gazebo(*o); };
}

}  // namespace rfidray::cli
