#pragma once
// Gazebo's entity ids ↔ our world entities. Gazebo names every entity by a number in its pose messages; the
// /world/<name>/scene/info service (ignition.msgs.Scene) gives the tree of models, nested models, links and
// sensors with ids, names and poses relative to the parent. We walk it with scoped names and match them to
// the entities of the SDF world (same names, since both come from the same file).
#include <ignition/msgs/pose.pb.h>
#include <ignition/msgs/pose_v.pb.h>
#include <ignition/msgs/scene.pb.h>

#include <optional>
#include <unordered_map>

#include "adapters/gazebo/gazebo_world.h"

namespace rfidray::gazebo {

// What one Gazebo entity id stands for here.
struct EntityRef {
  enum class Kind { kEntity, kAntenna, kTag };  // a model/link, or the sensor of an antenna/tag mount
  Kind kind = Kind::kEntity;
  size_t index = 0;  // into GazeboWorld::entities, antenna_mounts or tag_mounts
};

struct EntityMap {
  std::unordered_map<uint64_t, EntityRef> by_id;
  std::vector<std::string> missing;  // our entities the scene does not have (their SDF poses are kept)
  size_t matched = 0;
};

Pose from_msg(const ignition::msgs::Pose& p);
// The pose of a message from outside, or nullopt when it cannot be a pose: a position that is not finite or
// beyond core/limits.h's coordinate range, an orientation that is not finite or has a norm below 1e-6 (a zero
// quaternion). The orientation is normalized. A bridge must not let one bad message put NaN into its scene.
std::optional<Pose> checked_from_msg(const ignition::msgs::Pose& p);
void to_msg(const Pose& pose, ignition::msgs::Pose& out);

// Matches the scene's entities to the world's and sets the world's poses to the scene's (the current ones,
// so nothing depends on the first pose message, which discovery can lose).
EntityMap map_scene(const ignition::msgs::Scene& scene, GazeboWorld& world);

// The entity an element of a Pose_V names: by id when the map knows it, otherwise by a unique name (scoped
// or own), for a peer that did not answer scene/info. nullopt: not ours (visuals, collisions, lights, ...).
std::optional<EntityRef> resolve(const EntityMap& map, const GazeboWorld& world, const ignition::msgs::Pose& p);

}  // namespace rfidray::gazebo
