#pragma once
// Closed triangle meshes of the SDF geometry primitives, centred at the origin of their frame as SDF places
// them, wound counter-clockwise seen from outside. Curved shapes are tessellated with vertices on the exact
// surface at azimuths 2πk/segments (and, for the sphere, polar angles πj/stacks), so with segment counts that
// are multiples of 4 the bounding box is exact.
#include "raytrace/triangle_mesh.h"

namespace rfidray {

inline constexpr int kCylinderSegments = 32;
inline constexpr int kSphereSlices = 32;
inline constexpr int kSphereStacks = 16;

// size = full extents along x, y, z. 12 triangles.
TriangleMesh box_mesh(const Vec3& size);
// Axis along z, z in [−length/2, length/2]. 2·segments side triangles + (segments − 2) per cap.
TriangleMesh cylinder_mesh(double radius, double length, int segments = kCylinderSegments);
// 2·slices·(stacks − 1) triangles (a fan at each pole, quads between).
TriangleMesh sphere_mesh(double radius, int slices = kSphereSlices, int stacks = kSphereStacks);
// A finite rectangle through the origin with the given normal; size along the plane's own x, y axes (the
// plane's z axis turned onto `normal` by the shortest rotation). 2 triangles.
TriangleMesh plane_mesh(const Vec3& normal, double size_x, double size_y);

}  // namespace rfidray
