// Test helper: plays what Gazebo 11 with gazebo_ros (and a robot's TF publishers) sends, from a script file
// the test wrote. C++17 (ROS 1 headers). Usage: fake_gazebo11 SCRIPT TIMEOUT_S
//   static PARENT CHILD x y z qx qy qz qw   /tf_static (latched), sent first
//   step T                                  starts a step at simulation time T s
//   tf PARENT CHILD x y z qx qy qz qw       /tf, stamped T
//   model NAME x y z qx qy qz qw            one entry of /gazebo/model_states
//   noclock                                 no /clock (a bridge on /tf stamps does not subscribe to it)
//   await TOPIC N                           before the next step: wait until N rfid_sensor/TagArray messages
//                                           have come on TOPIC (the bridge has computed those ticks)
// Per step it publishes /tf, then /gazebo/model_states, then /clock (T): as Gazebo does, the clock passing
// a time comes after the poses of that time. Nothing is published before every topic has a subscriber (the
// bridge), and the queues are deep, so no message is lost. Exits 0 when all was sent, 1 on timeout.
#include <gazebo_msgs/ModelStates.h>
#include <rfid_sensor/TagArray.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_msgs/TFMessage.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

geometry_msgs::TransformStamped transform(std::istringstream& in, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  in >> t.header.frame_id >> t.child_frame_id >> t.transform.translation.x >> t.transform.translation.y >>
      t.transform.translation.z >> t.transform.rotation.x >> t.transform.rotation.y >> t.transform.rotation.z >>
      t.transform.rotation.w;
  t.header.stamp = stamp;
  return t;
}

struct Step {
  ros::Time time;
  tf2_msgs::TFMessage tf;
  gazebo_msgs::ModelStates models;
  std::string await_topic;  // a wait, not a step, when set
  int await_count = 0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  const double timeout_s = std::stod(argv[2]);
  std::ifstream script(argv[1]);
  if (!script) return 2;
  tf2_msgs::TFMessage statics;
  std::vector<Step> steps;
  bool with_clock = true;
  std::string line;
  while (std::getline(script, line)) {
    std::istringstream in(line);
    std::string kind;
    in >> kind;
    if (kind == "static") {
      statics.transforms.push_back(transform(in, ros::Time(0.0)));
    } else if (kind == "step") {
      double t = 0.0;
      in >> t;
      steps.push_back({ros::Time(t), {}, {}, "", 0});
    } else if (kind == "noclock") {
      with_clock = false;
    } else if (kind == "await") {
      Step w;
      in >> w.await_topic >> w.await_count;
      steps.push_back(w);
    } else if (kind == "tf") {
      steps.back().tf.transforms.push_back(transform(in, steps.back().time));
    } else if (kind == "model") {
      gazebo_msgs::ModelStates& m = steps.back().models;
      geometry_msgs::Pose p;
      std::string name;
      in >> name >> p.position.x >> p.position.y >> p.position.z >> p.orientation.x >> p.orientation.y >>
          p.orientation.z >> p.orientation.w;
      m.name.push_back(name);
      m.pose.push_back(p);
      m.twist.emplace_back();
    } else if (!kind.empty()) {
      return 2;
    }
  }

  ros::init(argc, argv, "fake_gazebo11", ros::init_options::AnonymousName | ros::init_options::NoRosout);
  const ros::WallTime start = ros::WallTime::now();
  auto timed_out = [&] { return (ros::WallTime::now() - start).toSec() > timeout_s; };
  while (!ros::master::check()) {
    if (timed_out()) return 1;
    ros::WallDuration(0.05).sleep();
  }
  ros::NodeHandle nh;
  const uint32_t queue = 1000000;
  ros::Publisher tf_static = nh.advertise<tf2_msgs::TFMessage>("/tf_static", queue, true);
  ros::Publisher tf = nh.advertise<tf2_msgs::TFMessage>("/tf", queue);
  ros::Publisher models = nh.advertise<gazebo_msgs::ModelStates>("/gazebo/model_states", queue);
  ros::Publisher clock = nh.advertise<rosgraph_msgs::Clock>("/clock", queue);
  std::map<std::string, int> received;
  std::vector<ros::Subscriber> listeners;
  for (const Step& s : steps)
    if (!s.await_topic.empty() && !received.count(s.await_topic)) {
      received[s.await_topic] = 0;
      int* n = &received[s.await_topic];
      listeners.push_back(nh.subscribe<rfid_sensor::TagArray>(s.await_topic, 100000,
                                                               [n](const rfid_sensor::TagArray::ConstPtr&) { ++*n; }));
    }
  std::vector<ros::Publisher*> outputs = {&tf_static, &tf, &models};
  if (with_clock) outputs.push_back(&clock);
  for (ros::Publisher* p : outputs)
    while (p->getNumSubscribers() == 0) {
      if (timed_out()) return 1;
      ros::WallDuration(0.01).sleep();
    }
  tf_static.publish(statics);
  for (const Step& s : steps) {
    if (!s.await_topic.empty()) {
      while (received[s.await_topic] < s.await_count) {
        if (timed_out()) return 1;
        ros::spinOnce();
        ros::WallDuration(0.002).sleep();
      }
      continue;
    }
    if (!s.tf.transforms.empty()) tf.publish(s.tf);
    if (!s.models.name.empty()) models.publish(s.models);
    if (with_clock) {
      rosgraph_msgs::Clock c;
      c.clock = s.time;
      clock.publish(c);
    }
  }
  // roscpp sends from a background thread: keep the node until the bridge has gone (it stops after its
  // --duration, having read everything) or, at most, 2 s.
  const ros::WallTime sent = ros::WallTime::now();
  auto subscribed = [&] {
    for (ros::Publisher* p : {&tf, &models, &clock})
      if (p->getNumSubscribers() > 0) return true;
    return false;
  };
  while (subscribed() && (ros::WallTime::now() - sent).toSec() < 2.0) ros::WallDuration(0.01).sleep();
  return 0;
}
