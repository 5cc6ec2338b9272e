#pragma once
// Procedural scene geometry: tessellated rectangles and boxes, metal racks with shelves, the paper's warehouse
// (scenes/paper_warehouse.obj is written from paper_warehouse_meshes()) and a parametric warehouse for
// benchmarks (rows × racks × shelves, optional tessellation) that reaches millions of triangles in memory.
//
// Geometry rules that keep the image method unambiguous: racks in a row are separated by a gap, posts stand
// 1 cm proud of the shelf plates and 5 cm above the top shelf, and no face rests on another, so no two
// surfaces coincide.
#include <string>
#include <vector>

#include "raytrace/triangle_mesh.h"

namespace rfidray {

// Rectangle corner + u·[0,1] + v·[0,1], split into nu × nv quads (2 triangles each).
void add_quad(TriangleMesh& mesh, const Vec3& corner, const Vec3& u, const Vec3& v, uint32_t material,
              int nu = 1, int nv = 1);
// Axis-aligned box [lo, hi]; each face split n × n; `with_bottom = false` leaves the face at lo.z() open.
void add_box(TriangleMesh& mesh, const Vec3& lo, const Vec3& hi, uint32_t material, int n = 1, bool with_bottom = true);

struct RackSpec {
  double front_x_m = 0.0;      // x of the face the tags are on (the aisle side)
  int facing = +1;             // +1: the rack extends towards +x from front_x (aisle at smaller x); −1: towards −x
  double y_min_m = 0.0, length_m = 2.0, depth_m = 1.0;
  std::vector<double> shelf_tops_m{0.15, 1.0, 2.0, 2.95};  // top surface of each shelf plate
  double plate_thickness_m = 0.03;
  double post_size_m = 0.08;
  int tessellation = 1;
};
TriangleMesh rack_mesh(const std::string& name, const RackSpec& spec, const std::string& material = "metal");

// The warehouse of D'Avella et al. (2022), Fig. 3/4, as used by scenes/paper_warehouse.yaml: concrete floor
// (x −8…7 m, y −13…11 m) and four 5 m concrete walls; metal racks either side of the robot's aisle:
// east row, shelf fronts at x = 2.95, y −9.5…1.0 with an open bay at y −4.4…−3.6 for the fixed antenna
// (shelf top 2.00 m; tags at x = 2.90, z = 2.05); west row, fronts at x = −4.90, y −9.5…7.2 (shelf top
// 1.80 m; tags at x = −4.85, z = 1.85). The aisle x = −1 (y −10…8) and the leg along y = 8 stay clear.
std::vector<TriangleMesh> paper_warehouse_meshes();

// A small hand-checkable scene: 20 × 20 m concrete ground plane at z = 0 centred on the origin, and one
// concrete wall sheet at x = 5 m (y −5…5, z 0…3).
std::vector<TriangleMesh> ground_and_wall_meshes();

struct WarehouseParams {
  int rows = 4;               // rows of racks (along y), aisles between them
  int racks_per_row = 10;
  int shelves = 4;
  double rack_length_m = 2.7, rack_depth_m = 1.0, shelf_spacing_m = 1.0, aisle_m = 3.0;
  int tessellation = 1;       // every rectangle split n × n (n² times the triangles)
  bool walls = true;
};
std::vector<TriangleMesh> generate_warehouse(const WarehouseParams& params);
// Triangle count generate_warehouse(params) produces (without building it).
size_t warehouse_triangle_count(const WarehouseParams& params);
// Throws InputError naming the field for out-of-range parameters.
void validate(const WarehouseParams& params);

}  // namespace rfidray
