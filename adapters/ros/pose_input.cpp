#include "adapters/ros/pose_input.h"

#include <gazebo_msgs/ModelStates.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <atomic>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>

namespace rfidray::ros_bridge {
namespace {

// roscpp drops the oldest message of a full subscription queue; the spinner empties it into our unbounded
// deque at once, so this only has to outlast a stall of the spinner.
constexpr uint32_t kQueue = 1000000;

PoseValue to_value(const geometry_msgs::Pose& p) {
  return {p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w};
}

}  // namespace

struct PoseInput::Impl {
  PoseInputOptions options;
  std::shared_ptr<RosSession> session;
  ros::CallbackQueue queue;
  std::unique_ptr<ros::NodeHandle> node;
  std::vector<ros::Subscriber> subs;
  std::unique_ptr<ros::AsyncSpinner> spinner;
  tf2::BufferCore buffer;  // thread-safe itself

  // Written by the spinner thread only; the events under the mutex.
  std::vector<geometry_msgs::TransformStamped> statics;
  double latest_tf_s = -std::numeric_limits<double>::infinity();  // newest /tf stamp
  double now_s = std::numeric_limits<double>::quiet_NaN();      // the time source's: /clock or /tf stamps
  std::mutex mutex;
  std::condition_variable cv;
  std::deque<InputEvent> events;
  std::atomic<uint64_t> messages{0}, resets{0};

  explicit Impl(const PoseInputOptions& o)
      : options(o), session(RosSession::get(o.node_name)), buffer(ros::Duration(o.tf_cache_s)) {}

  void push(InputEvent e) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      events.push_back(std::move(e));
    }
    cv.notify_one();
  }

  // A /tf stamp a second or more before the newest one: the simulator was reset. The TF buffer would refuse
  // the new (older) stamps, so it starts empty, with the static transforms. (Only /tf stamps count here: /tf
  // and /clock come on separate connections, and one may run ahead of the other.)
  void observe_tf(double t_s) {
    if (t_s + 1.0 < latest_tf_s) {
      buffer.clear();
      for (const auto& s : statics) buffer.setTransform(s, "rfidray", true);
      ++resets;
      latest_tf_s = t_s;
    } else if (t_s > latest_tf_s) {
      latest_tf_s = t_s;
    }
  }

  void on_clock(const rosgraph_msgs::Clock::ConstPtr& m) {
    ++messages;
    now_s = m->clock.toSec();
    push({InputEvent::Kind::kTime, now_s, {}});
  }

  void on_tf(const tf2_msgs::TFMessage::ConstPtr& m, bool is_static) {
    ++messages;
    double newest = -std::numeric_limits<double>::infinity();
    for (const auto& t : m->transforms) newest = std::max(newest, t.header.stamp.toSec());
    if (!is_static && newest > -std::numeric_limits<double>::infinity()) observe_tf(newest);
    for (const auto& t : m->transforms) {
      // tf2 reports a bad transform (NaN, empty or equal frame names) itself, on stderr, and keeps the rest.
      buffer.setTransform(t, "rfidray", is_static);
      if (is_static) {
        bool replaced = false;
        for (auto& s : statics)
          if (s.child_frame_id == t.child_frame_id) s = t, replaced = true;
        if (!replaced) statics.push_back(t);
      }
    }
    if (!is_static && !options.use_sim_time && newest > -std::numeric_limits<double>::infinity()) {
      now_s = latest_tf_s;
      push({InputEvent::Kind::kTime, now_s, {}});
    }
  }

  void on_model_states(const gazebo_msgs::ModelStates::ConstPtr& m) {
    ++messages;
    InputEvent e;
    e.kind = InputEvent::Kind::kModelStates;
    // No stamp in the message: it counts at the time it arrives at (NaN before any time was seen).
    e.time_s = now_s;
    const size_t n = std::min(m->name.size(), m->pose.size());
    for (size_t i = 0; i < n; ++i) e.models.push_back({m->name[i], to_value(m->pose[i])});
    push(std::move(e));
  }
};

PoseInput::PoseInput(const PoseInputOptions& options) : impl_(std::make_unique<Impl>(options)) {
  Impl& d = *impl_;
  d.node = std::make_unique<ros::NodeHandle>();
  d.node->setCallbackQueue(&d.queue);
  d.subs.push_back(d.node->subscribe<gazebo_msgs::ModelStates>(
      options.model_states_topic, kQueue, [&d](const gazebo_msgs::ModelStates::ConstPtr& m) { d.on_model_states(m); }));
  d.subs.push_back(d.node->subscribe<tf2_msgs::TFMessage>(
      "/tf", kQueue, [&d](const tf2_msgs::TFMessage::ConstPtr& m) { d.on_tf(m, false); }));
  d.subs.push_back(d.node->subscribe<tf2_msgs::TFMessage>(
      "/tf_static", kQueue, [&d](const tf2_msgs::TFMessage::ConstPtr& m) { d.on_tf(m, true); }));
  if (options.use_sim_time)
    d.subs.push_back(d.node->subscribe<rosgraph_msgs::Clock>(
        "/clock", kQueue, [&d](const rosgraph_msgs::Clock::ConstPtr& m) { d.on_clock(m); }));
  // One thread: callbacks run one at a time, in the order the messages were queued.
  d.spinner = std::make_unique<ros::AsyncSpinner>(1, &d.queue);
  d.spinner->start();
}

PoseInput::~PoseInput() {
  impl_->spinner->stop();
  impl_->subs.clear();
}

bool PoseInput::pop(InputEvent& out, double wait_s) {
  Impl& d = *impl_;
  std::unique_lock<std::mutex> lock(d.mutex);
  if (!d.cv.wait_for(lock, std::chrono::duration<double>(wait_s), [&] { return !d.events.empty(); })) return false;
  out = std::move(d.events.front());
  d.events.pop_front();
  return true;
}

bool PoseInput::lookup(const std::string& world_frame, const std::string& frame, double t_s, PoseValue& out,
                       std::string& error) const {
  if (!(t_s >= 0.0) || t_s > 4e9) {
    error = "time " + std::to_string(t_s) + " s is outside ROS time";
    return false;
  }
  try {
    // To tf2, time 0 means "the latest transforms": a tick at t = 0 reads the chain 1 ns later instead.
    const ros::Time t = t_s > 0.0 ? ros::Time(t_s) : ros::Time(0, 1);
    if (!impl_->buffer.canTransform(world_frame, frame, t, &error)) return false;
    const geometry_msgs::TransformStamped tr = impl_->buffer.lookupTransform(world_frame, frame, t);
    const auto& p = tr.transform.translation;
    const auto& q = tr.transform.rotation;
    out = {p.x, p.y, p.z, q.x, q.y, q.z, q.w};
    return true;
  } catch (const tf2::TransformException& e) {
    error = e.what();
    return false;
  }
}

std::string PoseInput::frames() const {
  std::vector<std::string> ids;
  impl_->buffer._getFrameStrings(ids);
  std::string s;
  for (const auto& id : ids) s += (s.empty() ? "" : ", ") + id;
  return s.empty() ? "none" : s;
}

std::string PoseInput::topics() const {
  std::string s;
  for (const ros::Subscriber& sub : impl_->subs) s += (s.empty() ? "" : ", ") + sub.getTopic();
  return s;
}

uint64_t PoseInput::messages() const { return impl_->messages; }
uint64_t PoseInput::resets() const { return impl_->resets; }

}  // namespace rfidray::ros_bridge
