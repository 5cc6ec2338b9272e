#include "adapters/gazebo/gazebo_world.h"

#include "core/error.h"

namespace rfidray::gazebo {

int GazeboWorld::find(const std::string& scoped_name) const {
  for (size_t i = 0; i < entities.size(); ++i)
    if (entities[i].scoped_name == scoped_name) return static_cast<int>(i);
  return -1;
}

Pose GazeboWorld::world_pose(size_t entity) const {
  Pose p = entities.at(entity).pose;
  for (int e = entities[entity].parent; e >= 0; e = entities[e].parent) p = entities[e].pose.compose(p);
  return p;
}

std::vector<TriangleMesh> GazeboWorld::world_meshes() const {
  std::vector<TriangleMesh> out;
  out.reserve(collisions.size());
  std::vector<std::optional<Pose>> cache(entities.size());
  for (const Collision& c : collisions) {
    if (!cache[c.link]) cache[c.link] = world_pose(c.link);
    TriangleMesh m = c.mesh;
    m.transform(*cache[c.link]);
    out.push_back(std::move(m));
  }
  return out;
}

void GazeboWorld::place_sensors() {
  for (size_t a = 0; a < scenario.antennas.size(); ++a) {
    const Mount& m = antenna_mounts[a];
    scenario.antennas[a].motion.kind = MotionSpec::Kind::kFixed;
    scenario.antennas[a].motion.pose = world_pose(m.entity).compose(m.pose);
  }
  for (size_t t = 0; t < scenario.tags.size(); ++t) {
    const Mount& m = tag_mounts[t];
    scenario.tags[t].motion.kind = MotionSpec::Kind::kFixed;
    scenario.tags[t].motion.pose = world_pose(m.entity).compose(m.pose);
  }
}

size_t GazeboWorld::triangle_count() const {
  size_t n = 0;
  for (const Collision& c : collisions) n += c.mesh.triangle_count();
  return n;
}

std::shared_ptr<const Scene> build_scene(const GazeboWorld& world) {
  try {
    return std::make_shared<const Scene>(world.world_meshes(), world.materials);
  } catch (const InputError& e) {
    throw InputError(world.file + ": materials: " + e.what());
  }
}

io::WorldSource load_world_source(const io::WorldSourceOptions& options, const std::string& default_material) {
  WorldOptions wo;
  wo.file = options.file;
  wo.resource_path = options.resource_path;
  wo.materials_file = options.materials_file;
  wo.default_material = default_material;
  const GazeboWorld world = load_world(wo);
  io::WorldSource out;
  out.scene = build_scene(world);
  out.scenario = world.scenario;
  out.warnings = world.warnings;
  out.notes = world.notes;
  for (const std::string& n : out.scene->notes()) out.notes.push_back(world.file + ": " + n);
  size_t models = 0, links = 0;
  for (const auto& e : world.entities) (e.kind == Entity::Kind::kModel ? models : links)++;
  out.summary = "world '" + world.name + "' (" + world.file + "): " + std::to_string(models) + " models, " +
                std::to_string(links) + " links, " + std::to_string(world.collisions.size()) + " collisions, " +
                std::to_string(world.triangle_count()) + " triangles, " +
                std::to_string(world.scenario.antennas.size()) + " antennas, " +
                std::to_string(world.scenario.tags.size()) + " tags";
  return out;
}

}  // namespace rfidray::gazebo
