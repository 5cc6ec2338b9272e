// `rfidray gazebo`: the live bridge to a running Gazebo (adapters/gazebo/bridge.h). Built only with the bridge;
// without it cli/commands.cpp registers a subcommand that says what is missing.
#include <CLI/CLI.hpp>
#include <memory>
#include <optional>

#include "adapters/gazebo/bridge.h"
#include "cli/commands.h"
#include "core/error.h"

namespace rfidray::cli {
namespace {

struct GazeboOptions {
  io::WorldSourceOptions world;
  std::string world_name, channel = "ideal", model, csv_dir, topic_prefix = "/rfid", ros_node = "gazebo";
  std::string partition, ip;
  uint64_t seed = 1;
  bool ros = false, quiet = false;
  std::optional<double> duration_s, idle_timeout_s;
  double scene_timeout_s = 10.0, connect_timeout_s = 2.0;
};

int run_gazebo(const GazeboOptions& o) {
  if (o.world.file.empty()) throw InputError("option --world: required (the SDF world Gazebo is running)");
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
  b.ros_node = o.ros_node;
  b.partition = o.partition;
  b.ip = o.ip;
  if (o.duration_s) b.duration_s = *o.duration_s;
  if (o.idle_timeout_s) b.idle_timeout_s = *o.idle_timeout_s;
  b.scene_timeout_s = o.scene_timeout_s;
  b.connect_timeout_s = o.connect_timeout_s;
  b.quiet = o.quiet;
  return gazebo::run_bridge(b);
}

}  // namespace

std::function<int()> setup_gazebo(CLI::App& app) {
  auto o = std::make_shared<GazeboOptions>();
  CLI::App* cmd = app.add_subcommand("gazebo", "Live bridge: follow a running Gazebo over ign-transport, publish readings");
  cmd->footer(
      "Loads the SDF world Gazebo runs (--world, as for simulate --world), asks /world/<name>/scene/info for the\n"
      "entity tree, follows /world/<name>/pose/info and /world/<name>/dynamic_pose/info (ignition.msgs.Pose_V,\n"
      "poses relative to the parent entity) and moves antennas, tags and obstacles. Each antenna reads at its\n"
      "update rate in simulation time (tick k at k / rate, the poses stamped at or before it), with the same\n"
      "reader model and random streams as `rfidray simulate`: the same poses and --seed give the same readings.\n"
      "Publishes per antenna tick:\n"
      "  ign-transport  <prefix>/<antenna>/readings  rfidray.msgs.TagReadings; <prefix>/status BridgeStatus\n"
      "  ROS 1 (--ros)  /<ros-node>/<antenna>/data   rfid_sensor/TagArray, as the seed plugin (~/<antenna>/data)\n"
      "  CSV (--csv D)  D/<antenna>.csv              the columns of `rfidray simulate`\n"
      "Discovery: peers must share the ign-transport partition (--partition, else IGN_PARTITION, else\n"
      "GZ_PARTITION, else hostname:username) and reach each other on IGN_IP (--ip; 127.0.0.1 on one machine).\n"
      "Stops after --duration s of simulation time, --idle-timeout s without poses, or on SIGINT/SIGTERM.");
  add_world_options(*cmd, o->world);
  cmd->add_option("--world-name", o->world_name, "Gazebo world name in topic names (default: the SDF's <world name>)");
  cmd->add_option("--seed", o->seed, "Random seed, >= 0")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--channel", o->channel, "ideal | los | los+blocked | single-bounce")->capture_default_str();
  cmd->add_option("--model", o->model, "Reader model of every antenna (paper | physical); default: the world's")
      ->check(CLI::IsMember({"paper", "physical"}));
  cmd->add_option("--csv", o->csv_dir, "Also write <antenna>.csv readings in this directory");
  cmd->add_option("--topic-prefix", o->topic_prefix, "Prefix of the ign-transport topics")->capture_default_str();
  cmd->add_flag("--ros", o->ros, "Also publish rfid_sensor/TagArray on ROS 1 (needs a running roscore, ROS_MASTER_URI)");
  cmd->add_option("--ros-node", o->ros_node, "ROS node name; topics are /<node>/<antenna>/data")->capture_default_str();
  cmd->add_option("--partition", o->partition, "ign-transport partition (overrides IGN_PARTITION)");
  cmd->add_option("--ip", o->ip, "IGN_IP: the address ign-transport discovery uses (e.g. 127.0.0.1)");
  cmd->add_option("--duration", o->duration_s, "Stop after this much simulation time (s)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--idle-timeout", o->idle_timeout_s, "Stop after this many wall seconds without pose messages")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--scene-timeout", o->scene_timeout_s, "Wait this long (s) for the scene/info service")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--connect-timeout", o->connect_timeout_s,
                  "Before the first tick, wait up to this long (s) for readings subscribers")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_flag("-q,--quiet", o->quiet, "Print only warnings and errors");
  return [o] { return run_gazebo(*o); };
}

}  // namespace rfidray::cli
