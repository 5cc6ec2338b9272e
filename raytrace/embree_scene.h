#pragma once
// The one place that talks to Embree 3: creates the device and the scene, adds one triangle geometry per
// mesh (geomID == mesh index), commits once, and releases both in the destructor. Read-only afterwards,
// so any number of threads may trace concurrently (Embree's rtcIntersect1/rtcOccluded1 are thread-safe on
// a committed scene; the intersect context lives on the caller's stack, nothing is allocated per ray).
//
// Packets (occluded_many with width 4, 8 or 16: rtcOccluded4/8/16) answer the same question for several segments
// at once. With the default (incoherent) context they give rtcOccluded1's booleans except on near-degenerate
// rays: one lying in a triangle's plane, or grazing a surface's edge, to float precision, which either
// kernel may call blocked (and the packet's answer may depend on its other lanes); with
// RTC_INTERSECT_CONTEXT_FLAG_COHERENT also rays through interior edges and vertices, so it is not used.
// tests/raytrace/test_packets.cpp checks random rays and rays ending at, passing through and starting on
// triangle edges and vertices. Which width is fastest depends on the scene
// and the rays (coherent short rays in an open scene: packets; long, mostly blocked rays in a big scene:
// single rays), so the caller measures it (raytrace/raytraced_channel.h).
//
// Embree works in float: hit distances are good to ~1e-7 relative. The triangles are the Scene's own float
// vertices (SceneMesh), which the image method reads too, widened to double; its arithmetic stays in double
// (raytrace/path_finder.cpp), and Embree only answers visibility and "which triangle is there".
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <span>
#include <string>

#include <embree3/rtcore.h>

#include "core/geometry.h"
#include "raytrace/scene_mesh.h"

namespace rfidray {

// Rays traced by the calling thread through any EmbreeScene (deterministic cost measure for `channel: auto`).
inline thread_local uint64_t tl_rays_traced = 0;

// A segment origin + t·dir, t in [tnear, tfar], `dir` unit length, world coordinates.
struct Segment {
  Vec3 origin = Vec3::Zero(), dir = Vec3::UnitX();
  double tnear = 0.0, tfar = 0.0;
};

// The triangle nearest to a point (EmbreeScene::nearest_triangle).
struct NearestTriangle {
  bool found = false;
  double distance_m = std::numeric_limits<double>::infinity();
  uint32_t geom = 0, prim = 0;  // mesh index, triangle index within the mesh
};

struct RayHit {
  bool hit = false;
  double t = std::numeric_limits<double>::infinity();  // distance along the (unit) direction, metres
  uint32_t geom = 0, prim = 0;                          // mesh index, triangle index within the mesh
};

class EmbreeScene {
 public:
  // Builds and commits the BVH. `config` is passed to rtcNewDevice (e.g. "threads=2"; "" = Embree default).
  // Embree stores float vertices relative to `origin` (Scene passes the bounding-box centre of scenes far from
  // the world origin, e.g. in UTM coordinates, so float precision is spent on the scene, not on its offset);
  // every query below takes world coordinates. Throws std::runtime_error if Embree reports an error.
  // Each mesh's vertex array (`vertex_xyz`, already about `origin`) is shared with Embree, not copied; so is its
  // index array (`triangles`) when its capacity exceeds its size (Embree may read up to 16 bytes past the last
  // triangle and the last vertex; Scene reserves those spare elements, and a vertex array without its spare
  // float is copied). The meshes must then outlive this object with those arrays neither modified nor
  // reallocated.
  explicit EmbreeScene(std::span<const SceneMesh> meshes, const std::string& config = "",
                       const Vec3& origin = Vec3::Zero());
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Closest hit on origin + t·dir for t in [tnear, tfar]; `dir` must be unit length.
  RayHit intersect(const Vec3& origin, const Vec3& dir, double tnear, double tfar) const {
    ++tl_rays_traced;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    fill_ray(rh.ray, origin - origin_, dir, tnear, tfar);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    RayHit out;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
      out.hit = true;
      out.t = rh.ray.tfar;
      out.geom = rh.hit.geomID;
      out.prim = rh.hit.primID;
    }
    return out;
  }

  // True if anything lies on origin + t·dir for t in [tnear, tfar].
  bool occluded(const Vec3& origin, const Vec3& dir, double tnear, double tfar) const {
    if (!(tfar > tnear)) return false;
    ++tl_rays_traced;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    fill_ray(ray, origin - origin_, dir, tnear, tfar);
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
  }

  // Which triangles a query looks through: skip(user, geom, prim) true for a triangle to ignore. Called inside
  // Embree's traversal, on the calling thread, for every triangle the ray meets: it must be cheap and must not
  // throw.
  using TriangleFilter = bool (*)(const void* user, uint32_t geom, uint32_t prim);

  // occluded() with the triangles `skip` accepts made transparent: true if any other triangle lies on
  // origin + t·dir for t in [tnear, tfar]. One traversal (Embree's intersect-context filter rejects the skipped
  // hits and the traversal goes on), however many skipped triangles the segment crosses. Counts one ray.
  bool occluded_except(const Vec3& origin, const Vec3& dir, double tnear, double tfar, TriangleFilter skip,
                       const void* user) const;

  // occluded() of each of the n segments s[0..n) into blocked[0..n), `width` segments per Embree call: 1 =
  // rtcOccluded1 each; 4, 8, 16 = rtcOccluded4/8/16 packets (segments with tfar ≤ tnear are inactive lanes and
  // not blocked, as in occluded()). Counts one ray per active segment. Throws std::invalid_argument for
  // another width.
  void occluded_many(int width, const Segment* s, size_t n, bool* blocked) const;

  // The triangle of `meshes` (the ones this scene was built from) nearest to `point` within `max_distance_m`
  // (Embree's rtcPointQuery over the BVH; exact closest point on each candidate triangle, in double from the
  // float vertices). Ties go to the lower (geom, prim). Thread-safe; allocates nothing.
  NearestTriangle nearest_triangle(const Vec3& point, double max_distance_m, std::span<const SceneMesh> meshes) const;

  RTCScene handle() const { return scene_; }  // for raw-Embree baselines in bench/ (coordinates − origin())
  const Vec3& origin() const { return origin_; }
  size_t triangle_count() const { return triangle_count_; }
  // Bytes Embree holds for this scene (geometry buffers and BVH), from its memory monitor.
  size_t embree_bytes() const { return static_cast<size_t>(std::max<int64_t>(0, embree_bytes_.load())); }

 private:
  static void fill_ray(RTCRay& r, const Vec3& o, const Vec3& d, double tnear, double tfar) {
    r.org_x = static_cast<float>(o.x());
    r.org_y = static_cast<float>(o.y());
    r.org_z = static_cast<float>(o.z());
    r.dir_x = static_cast<float>(d.x());
    r.dir_y = static_cast<float>(d.y());
    r.dir_z = static_cast<float>(d.z());
    r.tnear = static_cast<float>(tnear);
    r.tfar = static_cast<float>(tfar);
    r.time = 0.0f;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
  }

  std::atomic<int64_t> embree_bytes_{0};  // updated by Embree's build threads
  Vec3 origin_ = Vec3::Zero();
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  size_t triangle_count_ = 0;
};

}  // namespace rfidray
