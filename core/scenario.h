#pragma once
// A simulation scenario as plain data: what the YAML file (io/scenario_yaml) says, before any object is
// built. Trajectories are built from it by build_motion (core/simulation.h); the channel by its level
// (io/channel_factory). Other front ends (Gazebo worlds) fill it directly.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/channel_level.h"
#include "core/differential_drive.h"
#include "core/gen2_reader.h"
#include "core/geometry.h"
#include "core/mast.h"
#include "core/reader.h"

namespace rfidray {

// One mesh file of the scene. `material` (optional) maps every triangle of the file to one radio material;
// otherwise the file's own material names (OBJ usemtl) are looked up in SceneSpec::material_map.
struct MeshSpec {
  std::string file;      // as resolved against the scenario file's directory
  std::string material;  // "" = keep the file's material names
  Pose pose;             // placement of the mesh in the world
  Vec3 scale = Vec3::Ones();
  int source_line = 0;   // 1-based line in the scenario file (0: not from a file)
};

// A user-defined radio material (fixed ε' and σ, optional slab thickness), see core/material.h.
struct MaterialSpec {
  std::string name;
  double relative_permittivity = 1.0;
  double conductivity_s_m = 0.0;
  double thickness_m = 0.0;
  bool solid = false;  // faces bound closed solids (core/material.h RadioMaterial::solid)
  int source_line = 0;
};

struct MaterialMapEntry {
  std::string from;  // material name in the mesh file
  std::string to;    // radio material (builtin or MaterialSpec name)
};

struct SceneSpec {
  std::vector<MeshSpec> meshes;
  std::vector<MaterialSpec> materials;
  std::vector<MaterialMapEntry> material_map;
  std::string default_material;  // for unmapped names; "" = unknown names are an error
};

struct RobotSpec {
  std::string name = "robot";
  std::vector<Vec3> waypoints;  // x, y on the floor; z = height of the robot frame (normally 0)
  DifferentialDriveParams drive;
  int source_line = 0;
};

// How an antenna or a tag moves.
//   kFixed:     world = pose                                (mast: pose lifted by the mast height)
//   kRobot:     world = robot(t) ∘ mast(t) ∘ pose          (pose = mounting offset in the robot frame)
//   kWaypoints: position along waypoints at speed_m_s from the owner's start time, orientation = pose's
struct MotionSpec {
  enum class Kind { kFixed, kRobot, kWaypoints };
  Kind kind = Kind::kFixed;
  Pose pose;
  std::string robot;
  std::optional<MastParams> mast;
  std::vector<Vec3> waypoints;
  double speed_m_s = 0.0;
};

struct AntennaSpec {
  ReaderParams reader;  // reader.name names the antenna (and its CSV file)
  MotionSpec motion;
  double start_s = 0.0;  // the antenna reads from this time on
  int source_line = 0;
  // Set: this antenna is a Gen2 reader (core/gen2_reader.h): it and its ports read by inventory rounds instead of
  // ticks. Unset, and no other antenna's port: the tick model (core/simulation.h).
  std::optional<Gen2ReaderSpec> gen2;
};

struct TagSpec {
  TagParams tag;
  MotionSpec motion;
  double start_s = 0.0;  // the tag exists (can be read) from this time on; waypoint motion starts then too
  int source_line = 0;
};

// Settings of the ray-traced channels and of `channel: auto` (raytrace/trace_options.h, raytrace/fidelity.h).
// Unset fields keep the ray tracer's defaults.
struct ChannelOptionsSpec {
  std::optional<std::string> candidates;      // "exact" (also "fast", its former name) | "exhaustive"
  std::optional<int> candidate_rays;          // per-pose candidate search rays (0: exact)
  std::optional<double> candidate_spread;
  std::optional<double> drop_below_db;
  std::optional<double> max_path_length_m;
  std::optional<double> thin_post_max_width_m;  // full-selective, full: posts this thin scatter as cylinders (0 = off)
  std::optional<double> double_diffraction_max_m;  // full-selective, full: parallel edges this close diffract twice (0 = off)
  double auto_phase_tolerance_rad = 0.05;     // channel: auto
  double auto_rssi_tolerance_db = 0.5;
  size_t auto_sample_links = 2000;
  int source_line = 0;
};

struct Scenario {
  std::string source;  // scenario file, for messages ("" when built in code)
  SceneSpec scene;
  ChannelLevel channel = ChannelLevel::kIdeal;
  ChannelOptionsSpec channel_options;
  std::vector<RobotSpec> robots;
  std::vector<AntennaSpec> antennas;
  std::vector<TagSpec> tags;
  std::optional<double> duration_s;  // unset: until every finite motion (robot, moving tags) has ended
  uint64_t seed = 1;
};

}  // namespace rfidray
