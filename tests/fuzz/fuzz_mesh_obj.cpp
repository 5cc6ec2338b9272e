// libFuzzer harness: OBJ + MTL loading (raytrace/obj_loader) and scene building (facet merging, the Embree
// BVH). The input is split at the first line "#MTL": what precedes is fuzz.obj, what follows is fuzz.mtl (so
// `mtllib fuzz.mtl` reaches the MTL parser). When the scene builds, one link is traced at single-bounce and
// its paths must be finite. Invariants: tests/fuzz/fuzz_support.h.
#include <string>
#include <vector>

#include "raytrace/raytraced_channel.h"
#include "raytrace/scene.h"
#include "tests/fuzz/fuzz_support.h"

using namespace rfidray;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const size_t split = bytes.find("\n#MTL\n");
  const std::string obj = bytes.substr(0, split);
  const std::string mtl = split == std::string::npos ? std::string() : bytes.substr(split + 6);
  const auto obj_path = fuzz::write_scratch("fuzz.obj", obj);
  fuzz::write_scratch("fuzz.mtl", mtl);

  MaterialAssignment assignment;
  assignment.default_material = "metal";
  std::shared_ptr<const Scene> scene;
  if (!fuzz::run_guarded("fuzz.obj", [&] { scene = load_scene({obj_path}, assignment, {}, nullptr); })) return 0;

  Endpoint antenna, tag;
  antenna.pose.position = Vec3(0.3, -0.2, 1.1);
  tag.pose.position = Vec3(1.7, 0.9, 0.8);
  for (Endpoint* e : {&antenna, &tag}) {
    e->polarization.kind = PolarizationKind::kLinear;
    e->polarization.axis_local = Vec3::UnitZ();
  }
  TraceOptions options;
  options.level = ChannelLevel::kSingleBounce;
  fuzz::run_guarded("fuzz.obj", [&] {
    const RaytracedChannel channel(scene, options);
    for (const Path& p : channel.paths(antenna, tag, 866e6)) {
      fuzz::require_finite(p.length_m, "path length");
      fuzz::require_finite(p.contribution.real(), "path contribution");
      fuzz::require_finite(p.contribution.imag(), "path contribution");
    }
  });
  return 0;
}
