#include "adapters/gazebo/entity_map.h"

#include "core/limits.h"

namespace rfidray::gazebo {
namespace {

struct Walker {
  GazeboWorld& world;
  EntityMap& map;
  std::vector<bool> seen;

  void entity(uint64_t id, const std::string& scoped, const ignition::msgs::Pose* pose) {
    const int e = world.find(scoped);
    if (e < 0) return;
    map.by_id[id] = {EntityRef::Kind::kEntity, static_cast<size_t>(e)};
    if (pose)
      if (const auto checked = checked_from_msg(*pose)) world.entities[e].pose = *checked;  // else the SDF pose
    seen[e] = true;
    ++map.matched;
  }
  void sensors(const ignition::msgs::Link& link, const std::string& link_scoped) {
    const int e = world.find(link_scoped);
    if (e < 0) return;
    for (const auto& s : link.sensor()) {
      for (size_t a = 0; a < world.antenna_mounts.size(); ++a)
        if (world.antenna_mounts[a].entity == static_cast<size_t>(e) && world.antenna_mounts[a].sensor == s.name()) {
          map.by_id[s.id()] = {EntityRef::Kind::kAntenna, a};
          if (s.has_pose())
            if (const auto checked = checked_from_msg(s.pose())) world.antenna_mounts[a].pose = *checked;
        }
      for (size_t t = 0; t < world.tag_mounts.size(); ++t)
        if (world.tag_mounts[t].entity == static_cast<size_t>(e) && world.tag_mounts[t].sensor == s.name()) {
          map.by_id[s.id()] = {EntityRef::Kind::kTag, t};
          if (s.has_pose())
            if (const auto checked = checked_from_msg(s.pose())) world.tag_mounts[t].pose = *checked;
        }
    }
  }
  void model(const ignition::msgs::Model& m, const std::string& scope) {
    const std::string scoped = scope.empty() ? m.name() : scope + "::" + m.name();
    entity(m.id(), scoped, m.has_pose() ? &m.pose() : nullptr);
    for (const auto& l : m.link()) {
      entity(l.id(), scoped + "::" + l.name(), l.has_pose() ? &l.pose() : nullptr);
      sensors(l, scoped + "::" + l.name());
    }
    for (const auto& n : m.model()) model(n, scoped);
  }
};

}  // namespace

Pose from_msg(const ignition::msgs::Pose& p) {
  Pose out;
  out.position = Vec3(p.position().x(), p.position().y(), p.position().z());
  if (p.has_orientation()) {
    const Quat q(p.orientation().w(), p.orientation().x(), p.orientation().y(), p.orientation().z());
    out.orientation = q.norm() > 0.0 ? q.normalized() : Quat::Identity();
  }
  return out;
}

std::optional<Pose> checked_from_msg(const ignition::msgs::Pose& p) {
  const Vec3 position(p.position().x(), p.position().y(), p.position().z());
  if (!position.allFinite() || position.cwiseAbs().maxCoeff() > limits::kMaxCoordinateM) return std::nullopt;
  Pose out;
  out.position = position;
  if (p.has_orientation()) {
    const Quat q(p.orientation().w(), p.orientation().x(), p.orientation().y(), p.orientation().z());
    if (!q.coeffs().allFinite() || !(q.norm() > 1e-6)) return std::nullopt;
    out.orientation = q.normalized();
  }
  return out;
}

void to_msg(const Pose& pose, ignition::msgs::Pose& out) {
  out.mutable_position()->set_x(pose.position.x());
  out.mutable_position()->set_y(pose.position.y());
  out.mutable_position()->set_z(pose.position.z());
  out.mutable_orientation()->set_w(pose.orientation.w());
  out.mutable_orientation()->set_x(pose.orientation.x());
  out.mutable_orientation()->set_y(pose.orientation.y());
  out.mutable_orientation()->set_z(pose.orientation.z());
}

EntityMap map_scene(const ignition::msgs::Scene& scene, GazeboWorld& world) {
  EntityMap map;
  Walker w{world, map, std::vector<bool>(world.entities.size(), false)};
  for (const auto& m : scene.model()) w.model(m, "");
  for (size_t e = 0; e < world.entities.size(); ++e)
    if (!w.seen[e]) map.missing.push_back(world.entities[e].scoped_name);
  return map;
}

std::optional<EntityRef> resolve(const EntityMap& map, const GazeboWorld& world, const ignition::msgs::Pose& p) {
  if (auto it = map.by_id.find(p.id()); it != map.by_id.end()) return it->second;
  // With a scene map, an unknown id is an entity we do not track (visual, collision, light, ...).
  if (map.matched > 0 || p.name().empty()) return std::nullopt;
  int found = world.find(p.name());
  if (found < 0) {
    for (size_t e = 0; e < world.entities.size(); ++e)
      if (world.entities[e].name == p.name()) {
        if (found >= 0) return std::nullopt;  // ambiguous own name
        found = static_cast<int>(e);
      }
  }
  if (found < 0) return std::nullopt;
  return EntityRef{EntityRef::Kind::kEntity, static_cast<size_t>(found)};
}

}  // namespace rfidray::gazebo
