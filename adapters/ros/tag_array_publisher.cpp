#include "adapters/ros/tag_array_publisher.h"

#include <ros/ros.h>
#include <rfid_sensor/TagArray.h>

#include <cmath>
#include <stdexcept>

namespace rfidray::ros_bridge {

TagArrayPublisher::TagArrayPublisher(const std::string& node_name, const std::vector<std::string>& antennas,
                                     const std::string& topic_namespace, const std::string& frame_id)
    : session_(RosSession::get(node_name)), frame_id_(frame_id) {
  node_ = std::make_unique<ros::NodeHandle>(topic_namespace);
  // A deep queue: Gazebo running faster than real time gives bursts of ticks, and roscpp drops what does not fit.
  for (const std::string& a : antennas)
    publishers_.push_back(node_->advertise<rfid_sensor::TagArray>(a + "/data", 1000));
}

TagArrayPublisher::~TagArrayPublisher() {
  // roscpp sends from a background thread and drops what is still queued at shutdown (the last ticks of a
  // run that ends on --duration): give the queues time to drain. roscpp has no flush to wait on instead.
  if (!publishers_.empty()) ros::WallDuration(0.5).sleep();
  publishers_.clear();
  node_.reset();
}

std::string TagArrayPublisher::topics() const {
  std::string s;
  for (const ros::Publisher& p : publishers_) s += (s.empty() ? "" : ", ") + p.getTopic();
  return s;
}

bool TagArrayPublisher::all_connected() const {
  for (const ros::Publisher& p : publishers_)
    if (p.getNumSubscribers() == 0) return false;
  return true;
}

void TagArrayPublisher::publish(size_t antenna, double time_s, const PoseValue& pose, const std::vector<TagValue>& tags) {
  rfid_sensor::TagArray m;
  m.header.frame_id = frame_id_;
  m.header.stamp = ros::Time(time_s);
  m.antennaPose.position.x = pose.x;
  m.antennaPose.position.y = pose.y;
  m.antennaPose.position.z = pose.z;
  m.antennaPose.orientation.x = pose.qx;
  m.antennaPose.orientation.y = pose.qy;
  m.antennaPose.orientation.z = pose.qz;
  m.antennaPose.orientation.w = pose.qw;
  for (const TagValue& t : tags) {
    rfid_sensor::Tag tag;
    tag.name = t.name;
    tag.dist = t.dist;
    tag.phi = std::remainder(t.phase_rad, 2.0 * M_PI);
    tag.rssi = t.rssi;
    m.tags.push_back(tag);
  }
  m.ntags = static_cast<uint32_t>(m.tags.size());
  publishers_.at(antenna).publish(m);
}

}  // namespace rfidray::ros_bridge
