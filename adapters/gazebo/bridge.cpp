#include "adapters/gazebo/bridge.h"

#include <ignition/msgs/empty.pb.h>
#include <ignition/msgs/pose_v.pb.h>
#include <ignition/msgs/scene.pb.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <ignition/transport/Node.hh>
#include <memory>
#include <mutex>
#include <thread>

#include "adapters/gazebo/live_world.h"
#include "adapters/gazebo/msgs/rfid_readings.pb.h"
#include "adapters/gazebo/tick_csv.h"
#include "core/error.h"
#include "core/reader_model.h"

#ifdef RFIDRAY_HAVE_ROS
#include "adapters/ros/tag_array_publisher.h"
#include "core/number_text.h"
#endif

namespace rfidray::gazebo {
namespace {

double seconds(const ignition::msgs::Time& t) { return static_cast<double>(t.sec()) + 1e-9 * t.nsec(); }
void set_time(double t_s, ignition::msgs::Time& out) {
  const double sec = std::floor(t_s);
  out.set_sec(static_cast<int64_t>(sec));
  out.set_nsec(static_cast<int32_t>(std::llround((t_s - sec) * 1e9)));
}

// Pose_V messages from the transport threads to the main loop, in arrival order.
class Inbox {
 public:
  void push(const ignition::msgs::Pose_V& m) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(m);
    }
    cv_.notify_one();
  }
  bool pop(ignition::msgs::Pose_V& out, std::chrono::milliseconds wait) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!cv_.wait_for(lock, wait, [&] { return !queue_.empty(); })) return false;
    out = std::move(queue_.front());
    queue_.pop_front();
    return true;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<ignition::msgs::Pose_V> queue_;
};

std::string partition_of(const BridgeOptions& o, std::string& from) {
  if (!o.partition.empty()) return from = "--partition", o.partition;
  for (const char* v : {"IGN_PARTITION", "GZ_PARTITION"})
    if (const char* p = std::getenv(v); p && *p) return from = v, p;
  return from = "ign-transport default (hostname:username)", "";
}

}  // namespace

int run_bridge(const BridgeOptions& o) {
  auto say = [&](const std::string& s) {
    if (!o.quiet) std::fprintf(stderr, "rfidray gazebo: %s\n", s.c_str());
  };
  GazeboWorld world = load_bridge_world(o.world, o.model);
  const std::string name = o.world_name.empty() ? world.name : o.world_name;
  if (o.topic_prefix.empty() || o.topic_prefix[0] != '/')
    throw InputError("option --topic-prefix: must start with '/' (got '" + o.topic_prefix + "')");

  // Discovery settings, explicit: ign-transport reads IGN_IP when its first node is made.
  if (!o.ip.empty()) ::setenv("IGN_IP", o.ip.c_str(), 1);
  std::string partition_from;
  const std::string partition = partition_of(o, partition_from);
  // Declared before the node: the node's callbacks push into it until the node is gone.
  Inbox inbox;
  ignition::transport::NodeOptions node_options;
  if (!partition.empty()) node_options.SetPartition(partition);
  ignition::transport::Node node(node_options);
  const char* ip = std::getenv("IGN_IP");
  say("world '" + name + "' from " + o.world.file + "; ign-transport partition '" + node_options.Partition() +
      "' (" + partition_from + "), IGN_IP " + (ip && *ip ? std::string(ip) : std::string("unset (all interfaces)")));

  LiveOptions live_options;
  live_options.seed = o.seed;
  live_options.channel = o.channel;
  live_options.duration_s = o.duration_s;
  LiveWorld live(std::move(world), live_options);
  const Scenario& scenario = live.scenario();

  // Outputs.
  std::vector<ignition::transport::Node::Publisher> readings_pubs;
  for (const AntennaSpec& a : scenario.antennas) {
    const std::string topic = o.topic_prefix + "/" + a.reader.name + "/readings";
    readings_pubs.push_back(node.Advertise<rfidray::msgs::TagReadings>(topic));
    if (!readings_pubs.back()) throw InputError("cannot advertise ign-transport topic '" + topic + "'");
  }
  const std::string status_topic = o.topic_prefix + "/status";
  auto status_pub = node.Advertise<rfidray::msgs::BridgeStatus>(status_topic);
  TickCsv csv(o.csv_dir, scenario);
#ifdef RFIDRAY_HAVE_ROS
  std::unique_ptr<ros_bridge::TagArrayPublisher> ros_pub;
  if (o.ros) {
    std::vector<std::string> names;
    for (const AntennaSpec& a : scenario.antennas) names.push_back(a.reader.name);
    try {
      ros_pub = std::make_unique<ros_bridge::TagArrayPublisher>(o.ros_node, names);
    } catch (const std::runtime_error& e) {
      throw InputError(std::string("option --ros: ") + e.what());
    }
    say("ROS: publishing rfid_sensor/TagArray on " + ros_pub->topics());
  }
#else
  if (o.ros) throw InputError("option --ros: rfidray was built without roscpp (install libroscpp-dev and rebuild)");
#endif

  // The entity tree and current poses. Retried until the service is found: Gazebo may still be starting.
  const std::string scene_service = "/world/" + name + "/scene/info";
  {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.scene_timeout_s);
    bool got = false;
    while (!got && !stop_requested() && std::chrono::steady_clock::now() < until) {
      ignition::msgs::Empty req;
      ignition::msgs::Scene rep;
      bool ok = false;
      if (node.Request(scene_service, req, 1000u, rep, ok) && ok) {
        live.entity_map() = map_scene(rep, live.world());
        got = true;
      }
    }
    if (!got)
      throw InputError("no answer from " + scene_service + " within " + num(o.scene_timeout_s) +
                       " s: is Gazebo running world '" + name + "' in partition '" + node_options.Partition() +
                       "' (IGN_PARTITION) and reachable (IGN_IP)?");
    const EntityMap& map = live.entity_map();
    say("scene/info: " + std::to_string(map.matched) + " entities matched" +
        (map.missing.empty() ? std::string() : ", " + std::to_string(map.missing.size()) +
                                                   " of the SDF world not in Gazebo's scene (first: " + map.missing[0] + ")"));
  }

  std::function<void(const ignition::msgs::Pose_V&)> on_poses = [&](const ignition::msgs::Pose_V& m) { inbox.push(m); };
  const std::vector<std::string> pose_topics = {"/world/" + name + "/pose/info", "/world/" + name + "/dynamic_pose/info"};
  for (const std::string& topic : pose_topics)
    if (!node.Subscribe(topic, on_poses)) throw InputError("cannot subscribe to '" + topic + "'");

  // The first reading after advertising is lost unless the subscribers are known: wait for them, bounded.
  if (o.connect_timeout_s > 0.0) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.connect_timeout_s);
    auto all = [&] {
      for (const auto& p : readings_pubs)
        if (!p.HasConnections()) return false;
#ifdef RFIDRAY_HAVE_ROS
      if (ros_pub && !ros_pub->all_connected()) return false;
#endif
      return true;
    };
    while (!all() && !stop_requested() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!all()) say("no subscriber on some readings topics after --connect-timeout; publishing anyway");
  }

  install_stop_handlers();
  say("following /world/" + name + "/pose/info and dynamic_pose/info; readings on " + o.topic_prefix +
      "/<antenna>/readings" + (o.csv_dir.empty() ? "" : ", CSV in " + o.csv_dir));

  uint64_t pose_messages = 0;
  auto sink = [&](const TickReadings& t) {
    rfidray::msgs::TagReadings m;
    set_time(t.time_s, *m.mutable_header()->mutable_stamp());
    m.set_antenna(scenario.antennas[t.antenna].reader.name);
    to_msg(t.antenna_pose, *m.mutable_antenna_pose());
    m.set_tick(t.tick);
    m.set_frequency_hz(t.frequency_hz);
    m.set_channel(t.hop_index);  // the message keeps the CSV's column name
    for (const ReadRecord& r : t.reads) {
      auto* tag = m.add_tags();
      tag->set_name(scenario.tags[r.tag].tag.name);
      tag->set_dist(r.distance_m);
      tag->set_phase_rad(r.reading.phase_rad);
      tag->set_rssi(r.reading.rssi_dbm);
    }
    readings_pubs[t.antenna].Publish(m);
    csv.write(scenario, t);
#ifdef RFIDRAY_HAVE_ROS
    if (ros_pub) {
      std::vector<ros_bridge::TagValue> tags;
      for (const ReadRecord& r : t.reads)
        tags.push_back({scenario.tags[r.tag].tag.name, r.distance_m, r.reading.phase_rad, r.reading.rssi_dbm});
      const Pose& p = t.antenna_pose;
      ros_pub->publish(t.antenna, t.time_s,
                       {p.position.x(), p.position.y(), p.position.z(), p.orientation.x(), p.orientation.y(),
                        p.orientation.z(), p.orientation.w()},
                       tags);
    }
#endif
  };

  auto last_message = std::chrono::steady_clock::now();
  ignition::msgs::Pose_V msg;
  while (!stop_requested() && !live.finished()) {
    if (!inbox.pop(msg, std::chrono::milliseconds(100))) {
      const double idle = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_message).count();
      if (idle > o.idle_timeout_s) {
        say("no pose message for " + num(o.idle_timeout_s) + " s; stopping");
        break;
      }
      continue;
    }
    last_message = std::chrono::steady_clock::now();
    const uint64_t rejected_before = live.rejected_poses();
    live.apply(msg.has_header() ? seconds(msg.header().stamp()) : live.time_s(), msg, sink);
    ++pose_messages;
    if (rejected_before == 0 && live.rejected_poses() > 0)
      say("warning: dropped a malformed pose (not finite, beyond the coordinate range or a zero quaternion): " +
          live.first_rejected_pose() + "; further ones are counted in /rfid/status");
    rfidray::msgs::BridgeStatus st;
    set_time(live.time_s(), *st.mutable_header()->mutable_stamp());
    st.set_world(name);
    st.set_pose_messages(pose_messages);
    st.set_ticks(live.ticks());
    st.set_entities_matched(static_cast<uint32_t>(live.entity_map().matched));
    st.set_rejected_poses(live.rejected_poses());
    status_pub.Publish(st);
  }
  for (const std::string& topic : pose_topics) node.Unsubscribe(topic);
  say(std::to_string(live.ticks()) + " antenna ticks from " + std::to_string(pose_messages) + " pose messages (" +
      std::to_string(live.rejected_poses()) + " malformed poses dropped), " + std::to_string(live.scene_builds()) +
      " scene builds, simulation time " + num(live.time_s()) + " s");
  return 0;
}

}  // namespace rfidray::gazebo
