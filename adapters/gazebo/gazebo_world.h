#pragma once
// Adapter gazebo (target rfidray_gazebo) — owns SDF world import (sdformat 12) and the live bridge over
// ign-transport 11; translates Gazebo's entities, sensors and poses into io/core values at the edge.
//
// A Gazebo world as rfidray uses it: the entity tree (models, nested models, links) with poses relative to
// the parent entity — the form in which Gazebo publishes them on /world/<name>/pose/info — the collision
// surfaces of each link in the link frame, and the RFID antennas and tags mounted on links. Composing the
// tree gives world poses; the scenario (antennas and tags fixed where the world puts them) and the world-frame
// meshes follow from the current poses, so a live bridge moves entities and recomputes them.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "adapters/gazebo/material_rules.h"
#include "core/scenario.h"
#include "io/world_source.h"
#include "raytrace/material_map.h"
#include "raytrace/scene.h"
#include "raytrace/triangle_mesh.h"

namespace rfidray::gazebo {

struct Entity {
  enum class Kind { kModel, kLink };
  Kind kind = Kind::kModel;
  std::string name;         // own name
  std::string scoped_name;  // "rack_row::rack1::beam"
  int parent = -1;          // index of the parent model, −1: the world
  Pose pose;                // relative to the parent
  bool is_static = false;
};

// One <collision> of a link: its surface in the link frame (collision pose and mesh scale applied).
struct Collision {
  size_t link = 0;          // entity index
  std::string scoped_name;  // "barrel::link::ball" (also the TriangleMesh name)
  std::string geometry;     // box | cylinder | sphere | plane | mesh:<file>
  TriangleMesh mesh;
};

// Where an antenna or tag sits: the entity it is mounted on and its pose in that entity's frame.
struct Mount {
  size_t entity = 0;
  Pose pose;
  std::string sensor;  // sensor name
  std::string frame;   // antennas: the TF frame of <frame> (ROS pose input), "" = none
  int line = 0;        // of the <sensor> element
};

struct GazeboWorld {
  std::string file;  // the SDF file
  std::string name;  // <world name>
  std::vector<Entity> entities;
  std::vector<Collision> collisions;
  Scenario scenario;                  // antennas, tags (fixed), seed 1, channel "ideal", no duration
  std::vector<Mount> antenna_mounts;  // index-aligned with scenario.antennas
  std::vector<Mount> tag_mounts;      // index-aligned with scenario.tags
  MaterialAssignment materials;       // by_mesh filled from the rules for every collision
  std::vector<std::string> warnings;  // sdformat's (and the mesh loaders') complaints that did not stop the import
  std::vector<std::string> notes;     // defaults applied

  // Index of the entity with this scoped name, −1 if none.
  int find(const std::string& scoped_name) const;
  Pose world_pose(size_t entity) const;
  // Every collision surface in the world frame at the current entity poses.
  std::vector<TriangleMesh> world_meshes() const;
  // Sets each antenna's and tag's fixed pose (scenario) from the current entity poses.
  void place_sensors();
  size_t triangle_count() const;
};

struct WorldOptions {
  std::string file;
  std::vector<std::string> resource_path;  // --resource-path entries (searched before the environment)
  std::string materials_file;              // "" = none
  std::string default_material;            // overrides the file's default_material when set
};

// Loads an SDF world with sdformat 12. Throws InputError naming the file (and line, when sdformat or the
// sensor says) when the world cannot be used; complaints that leave a usable world go to `warnings`.
GazeboWorld load_world(const WorldOptions& options);

// The radio scene of the world at its current poses.
std::shared_ptr<const Scene> build_scene(const GazeboWorld& world);

// load_world + build_scene as io's world source (the loader cli registers with io::register_world_loader).
io::WorldSource load_world_source(const io::WorldSourceOptions& options, const std::string& default_material);

}  // namespace rfidray::gazebo
