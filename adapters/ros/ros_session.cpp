#include "adapters/ros/ros_session.h"

#include <ros/ros.h>

#include <sstream>
#include <stdexcept>

namespace rfidray::ros_bridge {
namespace {

std::weak_ptr<RosSession>& current() {
  static std::weak_ptr<RosSession> s;
  return s;
}

std::string to_text(XmlRpc::XmlRpcValue& v) {
  std::ostringstream out;
  out.precision(17);
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeString: return static_cast<std::string&>(v);
    case XmlRpc::XmlRpcValue::TypeBoolean: return static_cast<bool&>(v) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeInt: out << static_cast<int&>(v); return out.str();
    case XmlRpc::XmlRpcValue::TypeDouble: out << static_cast<double&>(v); return out.str();
    case XmlRpc::XmlRpcValue::TypeArray:
      for (int i = 0; i < v.size(); ++i) out << (i ? "," : "") << to_text(v[i]);
      return out.str();
    case XmlRpc::XmlRpcValue::TypeStruct: {
      bool first = true;
      for (auto& [key, value] : v) out << (first ? "" : ",") << key << "=" << to_text(value), first = false;
      return out.str();
    }
    default: throw std::runtime_error("unsupported value type");
  }
}

}  // namespace

std::shared_ptr<RosSession> RosSession::get(const std::string& node_name, const std::vector<std::string>& ros_args) {
  if (auto s = current().lock()) return s;
  if (!ros::isInitialized()) {
    ros::M_string remappings;
    for (const std::string& a : ros_args) {
      const size_t at = a.find(":=");
      if (at == std::string::npos || at == 0)
        throw std::runtime_error("'" + a + "' is not a ROS argument (NAME:=VALUE)");
      remappings[a.substr(0, at)] = a.substr(at + 2);
    }
    ros::init(remappings, node_name, ros::init_options::NoSigintHandler | ros::init_options::NoRosout);
  }
  if (!ros::master::check())
    throw std::runtime_error("no ROS master at " + ros::master::getURI() + " (start roscore, or set ROS_MASTER_URI)");
  ros::start();
  std::shared_ptr<RosSession> s(new RosSession());
  current() = s;
  return s;
}

RosSession::~RosSession() {
  if (ros::isStarted()) ros::shutdown();
}

std::string RosSession::node_name() const { return ros::this_node::getName(); }
std::string RosSession::master_uri() const { return ros::master::getURI(); }

std::map<std::string, std::string> RosSession::private_params() const {
  std::map<std::string, std::string> out;
  const std::string prefix = ros::this_node::getName() + "/";
  std::vector<std::string> names;
  if (!ros::param::getParamNames(names)) return out;
  ros::NodeHandle node("~");
  for (const std::string& n : names) {
    if (n.compare(0, prefix.size(), prefix) != 0) continue;
    // A dictionary's entries are listed one by one: read the dictionary once, by its own key.
    const std::string key = n.substr(prefix.size(), n.find('/', prefix.size()) - prefix.size());
    if (out.count(key)) continue;
    XmlRpc::XmlRpcValue v;
    if (!node.getParam(key, v)) continue;
    try {
      out[key] = to_text(v);
    } catch (const std::runtime_error&) {
      throw std::runtime_error("ROS parameter " + n + ": unsupported value type (use a string, number, boolean, "
                               "list or dictionary)");
    }
  }
  return out;
}

bool RosSession::use_sim_time() const {
  bool sim = false;
  ros::param::get("/use_sim_time", sim);
  return sim;
}

}  // namespace rfidray::ros_bridge
