#include "raytrace/embree_scene.h"

#include <stdexcept>

namespace rfidray {
namespace {

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree error ") + std::to_string(e) + " in " + what);
}

}  // namespace

EmbreeScene::EmbreeScene(std::span<const TriangleMesh> meshes, const std::string& config, const Vec3& origin)
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
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    for (size_t m = 0; m < meshes.size(); ++m) {
      const TriangleMesh& mesh = meshes[m];
      if (mesh.triangles.empty()) continue;
      RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), mesh.vertices.size()));
      auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(uint32_t), mesh.triangles.size()));
      check(device_, "geometry buffers");
      for (size_t i = 0; i < mesh.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.vertices[i][k] - origin_[k]);
      for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) idx[3 * t + k] = mesh.triangles[t][k];
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

EmbreeScene::~EmbreeScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

}  // namespace rfidray
