#include "raytrace/embree_scene.h"

#include <stdexcept>
#include <type_traits>

static_assert(sizeof(std::array<uint32_t, 3>) == 3 * sizeof(uint32_t), "triangles are shared as RTC_FORMAT_UINT3");

namespace rfidray {
namespace {

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree error ") + std::to_string(e) + " in " + what);
}

}  // namespace

EmbreeScene::EmbreeScene(std::span<const SceneMesh> meshes, const std::string& config, const Vec3& origin)
    : origin_(origin) {
  device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!device_) throw std::runtime_error("Embree: cannot create device (config '" + config + "')");
  rtcSetDeviceMemoryMonitorFunction(
      device_,
      [](void* user, ssize_t bytes, bool) {
        static_cast<std::atomic<int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
        return true;  // never refuse an allocation
      },
      &embree_bytes_);
  try {
    scene_ = rtcNewScene(device_);
    // Robust traversal: rays through shared edges/vertices are not lost (the image method's reflection
    // points and the blocked-path crossings land on edges of tessellated surfaces).
    // The context filter: occluded_except's transparent triangles (the levels that never set one ran level with
    // the scene before it: 0.98–1.06× on single- and double-bounce, bench/results/levels/).
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    for (size_t m = 0; m < meshes.size(); ++m) {
      const SceneMesh& mesh = meshes[m];
      if (mesh.triangles.empty()) continue;
      RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      // Both arrays are shared, not copied (12 bytes per triangle and 12 per vertex), when they have the spare
      // element Embree's 16-byte loads may read past the end (rtcSetSharedGeometryBuffer(3)); Scene provides it.
      if (mesh.vertex_xyz.capacity() <= mesh.vertex_xyz.size()) {
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), mesh.vertex_count()));
        std::copy(mesh.vertex_xyz.begin(), mesh.vertex_xyz.begin() + 3 * mesh.vertex_count(), v);
      } else {
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.vertex_xyz.data(), 0,
                                   3 * sizeof(float), mesh.vertex_count());
      }
      if (mesh.triangles.capacity() <= mesh.triangles.size()) {
        auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(uint32_t), mesh.triangles.size()));
        for (size_t t = 0; t < mesh.triangles.size(); ++t)
          for (int k = 0; k < 3; ++k) idx[3 * t + k] = mesh.triangles[t][k];
      } else {
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.triangles.data(), 0,
                                   sizeof(mesh.triangles[0]), mesh.triangles.size());
      }
      check(device_, "geometry buffers");
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(scene_, g, static_cast<unsigned>(m));
      rtcReleaseGeometry(g);  // the scene holds the reference
      triangle_count_ += mesh.triangles.size();
    }
    rtcCommitScene(scene_);
    check(device_, "scene commit");
  } catch (...) {
    if (scene_) rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
    throw;
  }
}

namespace {

// Embree hands the filter the context it was given: the caller's skip test rides behind it.
struct SkipContext {
  RTCIntersectContext context;  // first member: Embree's pointer to it is a pointer to this
  EmbreeScene::TriangleFilter skip = nullptr;
  const void* user = nullptr;
};

// Rejecting a hit (valid = 0) makes Embree go on as if the triangle were not there.
void skip_filter(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const SkipContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 &&
        c->skip(c->user, RTCHitN_geomID(args->hit, args->N, i), RTCHitN_primID(args->hit, args->N, i)))
      args->valid[i] = 0;
}

}  // namespace

bool EmbreeScene::occluded_except(const Vec3& origin, const Vec3& dir, double tnear, double tfar,
                                  TriangleFilter skip, const void* user) const {
  if (!(tfar > tnear)) return false;
  ++tl_rays_traced;
  SkipContext c;
  rtcInitIntersectContext(&c.context);
  c.context.filter = skip_filter;
  c.skip = skip;
  c.user = user;
  RTCRay ray;
  fill_ray(ray, origin - origin_, dir, tnear, tfar);
  rtcOccluded1(scene_, &c.context, &ray);
  return ray.tfar < 0.0f;
}

namespace {

// One packet of width W (RTCRay4/8/16) over segments s[0..n), n ≤ W; the rays are rounded to float exactly as
// fill_ray does for rtcOccluded1.
template <int W, typename Packet, typename Fn>
void occluded_packet(const Segment* s, size_t n, const Vec3& offset, bool* blocked, Fn&& call) {
  alignas(64) Packet ray;
  alignas(64) int valid[W];
  for (int k = 0; k < W; ++k) {
    const bool active = static_cast<size_t>(k) < n && s[k].tfar > s[k].tnear;
    valid[k] = active ? -1 : 0;
    const Segment& g = s[std::min<size_t>(k, n - 1)];
    const Vec3 o = g.origin - offset;
    ray.org_x[k] = static_cast<float>(o.x());
    ray.org_y[k] = static_cast<float>(o.y());
    ray.org_z[k] = static_cast<float>(o.z());
    ray.dir_x[k] = static_cast<float>(g.dir.x());
    ray.dir_y[k] = static_cast<float>(g.dir.y());
    ray.dir_z[k] = static_cast<float>(g.dir.z());
    ray.tnear[k] = static_cast<float>(g.tnear);
    ray.tfar[k] = static_cast<float>(g.tfar);
    ray.time[k] = 0.0f;
    ray.mask[k] = 0xFFFFFFFFu;
    ray.id[k] = 0;
    ray.flags[k] = 0;
    if (active) ++tl_rays_traced;
  }
  call(valid, &ray);
  for (size_t k = 0; k < n; ++k) blocked[k] = valid[k] != 0 && ray.tfar[k] < 0.0f;
}

}  // namespace

void EmbreeScene::occluded_many(int width, const Segment* s, size_t n, bool* blocked) const {
  if (width != 1 && width != 4 && width != 8 && width != 16)
    throw std::invalid_argument("EmbreeScene::occluded_many: width must be 1, 4, 8 or 16 (got " +
                                std::to_string(width) + ")");
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // Incoherent mode (the default) although the caller's rays share an origin: with
  // RTC_INTERSECT_CONTEXT_FLAG_COHERENT Embree 3.13 answers differently from rtcOccluded1 for rays through a
  // triangle's vertex or edge (tests/raytrace/test_packets.cpp), without it only for near-degenerate rays
  // (embree_scene.h).
  const size_t step = static_cast<size_t>(width);
  for (size_t i = 0; i < n; i += step) {
    const size_t m = std::min(n - i, step);
    switch (width) {
      case 1:
        blocked[i] = occluded(s[i].origin, s[i].dir, s[i].tnear, s[i].tfar);
        break;
      case 4:
        occluded_packet<4, RTCRay4>(s + i, m, origin_, blocked + i,
                                    [&](const int* v, RTCRay4* r) { rtcOccluded4(v, scene_, &context, r); });
        break;
      case 8:
        occluded_packet<8, RTCRay8>(s + i, m, origin_, blocked + i,
                                    [&](const int* v, RTCRay8* r) { rtcOccluded8(v, scene_, &context, r); });
        break;
      case 16:
        occluded_packet<16, RTCRay16>(s + i, m, origin_, blocked + i,
                                      [&](const int* v, RTCRay16* r) { rtcOccluded16(v, scene_, &context, r); });
        break;
      default:
        break;  // checked above
    }
  }
}

namespace {

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 2005, §5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

struct PointQueryState {
  Vec3 point;  // about the scene's local origin
  std::span<const SceneMesh> meshes;
  NearestTriangle best;
};

bool nearest_triangle_callback(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<PointQueryState*>(args->userPtr);
  const SceneMesh& m = st->meshes[args->geomID];
  const auto& t = m.triangles[args->primID];
  const Vec3 q = closest_point_on_triangle(st->point, m.local_vertex(t[0]), m.local_vertex(t[1]), m.local_vertex(t[2]));
  const double d = (q - st->point).norm();
  const bool better = d < st->best.distance_m ||
                      (d == st->best.distance_m && (args->geomID < st->best.geom ||
                                                    (args->geomID == st->best.geom && args->primID < st->best.prim)));
  if (!better) return false;
  st->best = {true, d, args->geomID, args->primID};
  if (d < args->query->radius) {
    args->query->radius = static_cast<float>(d) * (1.0f + 1e-6f) + 1e-7f;  // keep ties reachable
    return true;
  }
  return false;
}

}  // namespace

NearestTriangle EmbreeScene::nearest_triangle(const Vec3& point, double max_distance_m,
                                              std::span<const SceneMesh> meshes) const {
  PointQueryState st{point - origin_, meshes, {}};
  st.best.distance_m = max_distance_m;
  RTCPointQuery q;
  q.x = static_cast<float>(st.point.x());
  q.y = static_cast<float>(st.point.y());
  q.z = static_cast<float>(st.point.z());
  q.time = 0.0f;
  q.radius = static_cast<float>(max_distance_m);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_, &q, &context, nearest_triangle_callback, &st);
  if (st.best.found && !(st.best.distance_m <= max_distance_m)) st.best = {};
  return st.best;
}

EmbreeScene::~EmbreeScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

}  // namespace rfidray
