// The SDF importer on the shipped test world (scenes/tests/gazebo/rfid_test.world): entity tree and world
// poses, triangle counts and bounding boxes of every collision (nested models, an <include>d model, a COLLADA
// file in centimetres with Z up, an STL, primitives), the broken-inertia warning, the seed and native sensor
// forms with the seed's defaults reported, the material map; and the errors of unusable worlds. Every
// expected value is computed by hand from the world file (its comments say so).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "adapters/gazebo/gazebo_world.h"
#include "adapters/gazebo/resource_path.h"
#include "core/error.h"
#include "core/units.h"
#include "raytrace/mesh_file.h"
#include "tests/support/input_error.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::gazebo {
namespace {

namespace fs = std::filesystem;
const std::string kDir = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/tests/gazebo";

WorldOptions test_world(const std::string& materials = "") {
  WorldOptions o;
  o.file = kDir + "/rfid_test.world";
  o.resource_path = {kDir + "/models"};
  o.materials_file = materials;
  return o;
}

const Collision& collision(const GazeboWorld& w, const std::string& scoped) {
  for (const Collision& c : w.collisions)
    if (c.scoped_name == scoped) return c;
  throw std::runtime_error("no collision " + scoped);
}

// World-frame bounds of one collision.
std::pair<Vec3, Vec3> world_bounds(const GazeboWorld& w, const std::string& scoped) {
  TriangleMesh m = collision(w, scoped).mesh;
  m.transform(w.world_pose(collision(w, scoped).link));
  return m.bounds();
}

// Primitives are built in double precision; assimp reads files in single precision (1e-7 relative).
constexpr double kExact = 1e-9, kFloat = 1e-6;

void expect_box(const std::pair<Vec3, Vec3>& b, const Vec3& lo, const Vec3& hi, double tol = kExact) {
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(b.first[i], lo[i], tol) << "min axis " << i;
    EXPECT_NEAR(b.second[i], hi[i], tol) << "max axis " << i;
  }
}

bool contains(const std::vector<std::string>& lines, const std::string& a, const std::string& b = "") {
  for (const auto& l : lines)
    if (l.find(a) != std::string::npos && l.find(b) != std::string::npos) return true;
  return false;
}

TEST(WorldImport, EntityTreeAndWorldPoses) {
  const GazeboWorld w = load_world(test_world());
  EXPECT_EQ(w.name, "rfid_test");
  size_t models = 0, links = 0;
  for (const Entity& e : w.entities) (e.kind == Entity::Kind::kModel ? models : links)++;
  EXPECT_EQ(models, 10u);  // ground rack_row rack1 spare crate barrel robot portal tag_1 tag_2
  EXPECT_EQ(links, 10u);
  const int rack1 = w.find("rack_row::rack1");
  ASSERT_GE(rack1, 0);
  EXPECT_EQ(w.entities[rack1].parent, w.find("rack_row"));
  // rack_row at (5, 0, 0) turned 90° about Z; rack1 1 m along rack_row's x → world (5, 1, 0).
  EXPECT_TRUE(w.entities[rack1].pose.position.isApprox(Vec3(1, 0, 0), 1e-12));
  const Pose beam = w.world_pose(w.find("rack_row::rack1::beam"));
  EXPECT_NEAR((beam.position - Vec3(5, 1, 0.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((beam.orientation * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((w.world_pose(w.find("spare")).position - Vec3(-4, -2, 0)).norm(), 0.0, 1e-12);
}

TEST(WorldImport, TriangleCountsAndBoundingBoxes) {
  const GazeboWorld w = load_world(test_world());
  // plane 2, STL 4, two COLLADA beams 12 each, box 12, cylinder 2·32 + 2·30 = 124, sphere 2·32·15 = 960.
  EXPECT_EQ(w.collisions.size(), 7u);
  EXPECT_EQ(w.triangle_count(), 2u + 4 + 12 + 12 + 12 + 124 + 960);
  EXPECT_EQ(collision(w, "ground::link::floor").mesh.triangle_count(), 2u);
  expect_box(world_bounds(w, "ground::link::floor"), {-10, -5, 0}, {10, 5, 0});
  // COLLADA, centimetres, Z up: 2 × 0.5 × 0.1 m at 1 m inside the file; link 0.5 m up; turned 90°: x → y.
  EXPECT_EQ(collision(w, "rack_row::rack1::beam::beam").mesh.triangle_count(), 12u);
  expect_box(world_bounds(w, "rack_row::rack1::beam::beam"), {4.5, 1, 1.5}, {5, 3, 1.6}, kFloat);
  // The same file, included at (−4, −2, 0) unturned.
  expect_box(world_bounds(w, "spare::beam::beam"), {-4, -2, 1}, {-2, -1.5, 1.1}, kFloat);
  // STL tetrahedron with unit legs, scale (2, 1, 1), 0.5 m up, turned 90° with rack_row.
  EXPECT_EQ(collision(w, "rack_row::base::post").mesh.triangle_count(), 4u);
  expect_box(world_bounds(w, "rack_row::base::post"), {4, 0, 0.5}, {5, 2, 1.5}, kFloat);
  expect_box(world_bounds(w, "crate::body::box"), {-2.5, 2, 0}, {-1.5, 4, 1});
  EXPECT_EQ(collision(w, "barrel::link::drum").mesh.triangle_count(), 124u);
  expect_box(world_bounds(w, "barrel::link::drum"), {-0.3, -3.3, 0}, {0.3, -2.7, 1});
  EXPECT_EQ(collision(w, "barrel::link::ball").mesh.triangle_count(), 960u);
  expect_box(world_bounds(w, "barrel::link::ball"), {-0.25, -3.25, 1}, {0.25, -2.75, 1.5});
  // Every vertex of the sphere is on the sphere.
  for (const Vec3& v : collision(w, "barrel::link::ball").mesh.vertices)
    EXPECT_NEAR((v - Vec3(0, 0, 1.25)).norm(), 0.25, 1e-12);
}

TEST(WorldImport, BrokenInertiaIsAWarningNotAnError) {
  const GazeboWorld w = load_world(test_world());
  EXPECT_TRUE(contains(w.warnings, "invalid inertia", "body")) << "warnings: " << w.warnings.size();
  EXPECT_GE(w.find("crate::body"), 0);  // the link is still there, with its collision
  EXPECT_EQ(collision(w, "crate::body::box").mesh.triangle_count(), 12u);
}

TEST(WorldImport, SeedAntennaGetsSeedDefaultsReported) {
  const GazeboWorld w = load_world(test_world());
  ASSERT_EQ(w.scenario.antennas.size(), 2u);
  const AntennaSpec& a = w.scenario.antennas[0];
  EXPECT_EQ(a.reader.name, "reader");
  EXPECT_EQ(a.reader.model, ReaderModelKind::kPaper);
  EXPECT_EQ(a.reader.frequencies_hz, std::vector<double>{865.7e6});
  EXPECT_DOUBLE_EQ(a.reader.noise_phi_rad, 0.1);
  EXPECT_DOUBLE_EQ(a.reader.update_rate_hz, 10.0);
  // Left out of the world: the seed plugin's defaults.
  EXPECT_DOUBLE_EQ(a.reader.noise_rssi, 0.005);
  EXPECT_DOUBLE_EQ(a.reader.range_m, 5.0);
  EXPECT_DOUBLE_EQ(a.reader.communication_gain, 250.0);
  EXPECT_TRUE(contains(w.notes, "sensor 'reader'", "noiserssi 0.005, range 5 m, communication_gain 250"));
  // normal_distribution (the seed's <random> name) with "0 0.05".
  EXPECT_EQ(a.reader.optional_distribution.kind, DistributionKind::kNormal);
  EXPECT_EQ(a.reader.optional_distribution.params, (std::vector<double>{0.0, 0.05}));
  EXPECT_TRUE(a.motion.pose.position.isApprox(Vec3(0, 0, 1.5)));
  EXPECT_EQ(a.source_line, 79);
}

TEST(WorldImport, NativeAntennaAndTags) {
  const GazeboWorld w = load_world(test_world());
  const AntennaSpec& g = w.scenario.antennas[1];
  EXPECT_EQ(g.reader.name, "gate");
  EXPECT_EQ(g.reader.model, ReaderModelKind::kPhysical);
  EXPECT_EQ(g.reader.frequencies_hz.size(), 4u);  // hopping: eu
  EXPECT_DOUBLE_EQ(g.reader.tx_power_dbm, 27.0);
  EXPECT_EQ(g.reader.pattern.kind, PatternKind::kPatch);
  EXPECT_DOUBLE_EQ(g.reader.pattern.peak_gain_dbi, 6.0);
  EXPECT_EQ(g.reader.polarization.kind, PolarizationKind::kCircularRight);
  EXPECT_DOUBLE_EQ(g.reader.update_rate_hz, 5.0);
  // Portal at (1, 4, 0), sensor 2 m up facing −Y (yaw −90°): boresight +X → −Y.
  EXPECT_TRUE(g.motion.pose.position.isApprox(Vec3(1, 4, 2)));
  EXPECT_NEAR((g.motion.pose.orientation * Vec3::UnitX() - Vec3(0, -1, 0)).norm(), 0.0, 1e-12);
  ASSERT_EQ(w.scenario.tags.size(), 2u);
  EXPECT_EQ(w.scenario.tags[0].tag.name, "tag_1::link");  // named after the parent link, as the seed does
  EXPECT_TRUE(w.scenario.tags[0].motion.pose.position.isApprox(Vec3(3, 0, 1.5)));
  EXPECT_EQ(w.scenario.tags[1].tag.name, "tag_2::link");
  EXPECT_DOUBLE_EQ(w.scenario.tags[1].tag.gain_dbi, 1.5);
  EXPECT_TRUE(w.scenario.tags[1].motion.pose.position.isApprox(Vec3(2, 2, 1)));
}

TEST(WorldImport, MaterialMapByModelLinkCollisionAndMeshMaterial) {
  const GazeboWorld w = load_world(test_world(kDir + "/rfid_test_materials.yaml"));
  const auto scene = build_scene(w);
  // Material of each mesh's first triangle (global ids follow the collision order).
  std::map<std::string, std::string> got;
  uint32_t first = 0;
  for (const SceneMesh& m : scene->meshes()) {
    got[m.name] = scene->materials()[scene->material_of(first)].name;
    first += static_cast<uint32_t>(m.triangle_count());
  }
  EXPECT_EQ(got["crate::body::box"], "crate_wood");          // models: crate
  EXPECT_EQ(got["rack_row::base::post"], "metal");           // models: rack_row
  EXPECT_EQ(got["rack_row::rack1::beam::beam"], "metal");    // nested: the parent model's rule
  EXPECT_EQ(got["barrel::link::drum"], "plasterboard");      // links
  EXPECT_EQ(got["barrel::link::ball"], "glass");             // collisions beat links
  EXPECT_EQ(got["spare::beam::beam"], "metal");              // mesh_materials: steel
  EXPECT_EQ(got["ground::link::floor"], "concrete");         // default_material
}

// `solid: true` in the material map: the material's collisions are closed solids (RadioMaterial::solid).
TEST(WorldImport, MaterialMapSolidFlag) {
  const testing::ScratchDir dir("world_solid");
  const std::string base = "default_material: concrete\nmodels: {crate: crate_wood}\nmaterials:\n";
  const auto write_map = [&](const std::string& entry) {
    const std::string path = (dir.path() / "materials.yaml").string();
    std::ofstream(path) << base << entry;
    return path;
  };
  const auto scene = build_scene(load_world(test_world(write_map(
      "  - {name: crate_wood, relative_permittivity: 2.0, conductivity_s_m: 0.01, thickness_m: 0.3, solid: true}\n"))));
  bool found = false;
  for (const RadioMaterial& m : scene->materials()) {
    if (m.name != "crate_wood") continue;
    found = true;
    EXPECT_TRUE(m.solid);
    EXPECT_DOUBLE_EQ(m.thickness_m, 0.3);
  }
  EXPECT_TRUE(found);
  const std::string e = testing::input_error_of([&] {
    load_world(test_world(write_map("  - {name: crate_wood, relative_permittivity: 2.0, solid: 3}\n")));
  });
  EXPECT_NE(e.find("materials[0].solid"), std::string::npos) << e;
}

TEST(MeshFile, ColladaYUpIsStoodUpAndScaled) {
  // The beam of beam.dae, but Y up in millimetres: its Y becomes Z, its Z becomes −Y.
  std::string text = testing::slurp(kDir + "/models/rack_part/meshes/beam.dae");
  auto swap = [&](const std::string& a, const std::string& b) { text.replace(text.find(a), a.size(), b); };
  swap("<unit name=\"centimeter\" meter=\"0.01\"/>", "<unit name=\"millimeter\" meter=\"0.001\"/>");
  swap("<up_axis>Z_UP</up_axis>", "<up_axis>Y_UP</up_axis>");
  const testing::ScratchDir dir("yup");
  const TriangleMesh m = load_mesh_file(dir.write("beam.dae", text));
  EXPECT_EQ(m.triangle_count(), 12u);
  expect_box(m.bounds(), {0, -0.11, 0}, {0.2, -0.1, 0.05}, kFloat);
  EXPECT_EQ(m.material_names, std::vector<std::string>{"steel"});
}

// --- unusable worlds -------------------------------------------------------------------------------------

class BadWorld : public ::testing::Test {
 protected:
  std::string write(const std::string& body) {
    file_ = dir_.write("bad.world", body);
    return file_.string();
  }
  std::string error_of(const std::string& body) {
    WorldOptions o;
    o.file = write(body);
    o.resource_path = {kDir + "/models"};
    return testing::input_error_of([&] { load_world(o); });
  }
  const testing::ScratchDir dir_{testing::ScratchDir::current_test_name("bad_world")};
  fs::path file_;
};

std::string world_with(const std::string& inner) {
  return "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\">\n<world name=\"w\">\n" + inner + "\n</world>\n</sdf>\n";
}

TEST_F(BadWorld, MissingFile) {
  WorldOptions o;
  o.file = "/nonexistent/x.world";
  EXPECT_THROW(load_world(o), InputError);
}

TEST_F(BadWorld, MalformedXml) {
  const std::string e = error_of("<sdf version=\"1.9\"><world name=\"w\"><model name=\"m\"></world>");
  EXPECT_NE(e.find("not a usable SDF world"), std::string::npos) << e;
  EXPECT_NE(e.find(file_.string()), std::string::npos) << e;
}

TEST_F(BadWorld, NoWorldElement) {
  const std::string e = error_of("<?xml version=\"1.0\"?><sdf version=\"1.9\"><model name=\"m\"><link name=\"l\"/></model></sdf>");
  EXPECT_NE(e.find("no <world>"), std::string::npos) << e;
}

// sdformat 12 throws std::invalid_argument from its version converter for these (found by the sdf_world fuzzer):
// an input error naming the file, the line and the attribute, never another exception.
TEST_F(BadWorld, VersionThatIsNotTwoNumbersNamesTheAttribute) {
  for (const std::string v : {"1.a", "1..6", "x.6", "1.99999999999", "1.6.x"}) {
    const std::string e = error_of("<?xml version=\"1.0\"?>\n<sdf version=\"" + v + "\">\n<world name=\"w\"/>\n</sdf>\n");
    EXPECT_NE(e.find("not a usable SDF world"), std::string::npos) << v << ": " << e;
    EXPECT_NE(e.find(file_.string() + ":2: <sdf version=\"" + v + "\"> is not a version"), std::string::npos)
        << v << ": " << e;
  }
}

TEST_F(BadWorld, UnknownModelUri) {
  const std::string e = error_of(world_with(
      "<model name=\"m\"><static>true</static><link name=\"l\"><collision name=\"c\"><geometry><mesh>"
      "<uri>model://no_such_model/meshes/x.dae</uri></mesh></geometry></collision></link></model>"));
  EXPECT_NE(e.find("model://no_such_model/meshes/x.dae"), std::string::npos) << e;
  EXPECT_NE(e.find("collision 'm::l::c'"), std::string::npos) << e;
  EXPECT_NE(e.find(":4:"), std::string::npos) << e;  // the <collision> line
}

TEST_F(BadWorld, BadSeedParameterNamesSensorAndField) {
  const std::string e = error_of(world_with(
      "<model name=\"m\"><link name=\"l\">\n<sensor name=\"ant\" type=\"rfid\"><update_rate>10</update_rate>"
      "<plugin name=\"p\" filename=\"f\"><noisephi>-1</noisephi></plugin></sensor></link></model>"));
  EXPECT_NE(e.find(":5: sensor 'ant'"), std::string::npos) << e;
  EXPECT_NE(e.find("noisephi"), std::string::npos) << e;
  EXPECT_NE(e.find(">= 0"), std::string::npos) << e;
}

TEST_F(BadWorld, UnknownNativeKeyIsAnError) {
  const std::string e = error_of(world_with(
      "<model name=\"m\"><link name=\"l\">\n<sensor name=\"ant\" type=\"custom\"><rfid_antenna>"
      "<tx_powr_dbm>30</tx_powr_dbm></rfid_antenna></sensor></link></model>"));
  EXPECT_NE(e.find("unknown key 'tx_powr_dbm'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'tx_power_dbm'"), std::string::npos) << e;
}

TEST_F(BadWorld, UnknownDistributionNamesTheValidOnes) {
  const std::string e = error_of(world_with(
      "<model name=\"m\"><link name=\"l\">\n<sensor name=\"ant\" type=\"rfid\"><plugin name=\"p\" filename=\"f\">"
      "<optional_distribution>poisson_distribution</optional_distribution></plugin></sensor></link></model>"));
  EXPECT_NE(e.find("unknown distribution 'poisson_distribution'"), std::string::npos) << e;
}

TEST_F(BadWorld, DuplicateAntennaNames) {
  const std::string s = "<sensor name=\"ant\" type=\"rfid\"><update_rate>1</update_rate></sensor>";
  const std::string e = error_of(world_with("<model name=\"a\"><link name=\"l\">" + s + "</link></model>"
                                            "<model name=\"b\"><link name=\"l\">" + s + "</link></model>"));
  EXPECT_NE(e.find("a second antenna named 'ant'"), std::string::npos) << e;
}

TEST(ResourcePath, EnvironmentAndFlagOrder) {
  const std::string models = kDir + "/models";
  ::setenv("IGN_GAZEBO_RESOURCE_PATH", ("/nonexistent:" + models).c_str(), 1);
  const auto dirs = resource_dirs({});
  ::unsetenv("IGN_GAZEBO_RESOURCE_PATH");
  ASSERT_EQ(dirs.size(), 1u);  // the missing directory is left out
  EXPECT_EQ(resolve_uri("model://rack_part/meshes/post.stl", "/", dirs), fs::path(models) / "rack_part/meshes/post.stl");
  EXPECT_THROW(resolve_uri("model://rack_part/meshes/post.stl", "/", {}), InputError);
  EXPECT_THROW(resolve_uri("https://fuel.example/models/x", "/", dirs), InputError);
}

}  // namespace
}  // namespace rfidray::gazebo
