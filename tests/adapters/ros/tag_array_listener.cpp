// Test helper: an ordinary roscpp subscriber of rfid_sensor/TagArray, as the seed plugin's users have.
// Usage: tag_array_listener TOPIC COUNT TIMEOUT_S OUTFILE — writes one line per message
//   stamp_s ntags px py pz qx qy qz qw frame_id {name dist phi rssi}...
// and exits 0 once COUNT messages arrived, 1 on timeout. C++17 (ROS 1 headers).
#include <ros/ros.h>
#include <rfid_sensor/TagArray.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  if (argc != 5) return 2;
  const std::string topic = argv[1];
  const int count = std::stoi(argv[2]);
  const double timeout_s = std::stod(argv[3]);
  std::FILE* out = std::fopen(argv[4], "w");
  if (!out) return 2;
  int c = 0;
  ros::init(argc, argv, "rfidray_test_listener", ros::init_options::AnonymousName | ros::init_options::NoRosout);
  const ros::WallTime start = ros::WallTime::now();
  while (!ros::master::check()) {
    if ((ros::WallTime::now() - start).toSec() > timeout_s) return 1;
    ros::WallDuration(0.05).sleep();
  }
  ros::NodeHandle nh;
  // A deep queue: the bridge publishes ticks in bursts when the simulation runs faster than real time.
  ros::Subscriber sub = nh.subscribe<rfid_sensor::TagArray>(topic, 100000, [&](const rfid_sensor::TagArray::ConstPtr& m) {
    std::fprintf(out, "%.17g %u %.17g %.17g %.17g %.17g %.17g %.17g %.17g %s", m->header.stamp.toSec(), m->ntags,
                 m->antennaPose.position.x, m->antennaPose.position.y, m->antennaPose.position.z,
                 m->antennaPose.orientation.x, m->antennaPose.orientation.y, m->antennaPose.orientation.z,
                 m->antennaPose.orientation.w, m->header.frame_id.c_str());
    for (const auto& t : m->tags) std::fprintf(out, " %s %.17g %.17g %.17g", t.name.c_str(), t.dist, t.phi, t.rssi);
    std::fprintf(out, "\n");
    std::fflush(out);
    ++c;
  });
  while (ros::ok() && c < count && (ros::WallTime::now() - start).toSec() < timeout_s) {
    ros::spinOnce();
    ros::WallDuration(0.005).sleep();
  }
  std::fclose(out);
  return c >= count ? 0 : 1;
}
