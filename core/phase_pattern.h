#pragma once
// Phase response of a real antenna or tag: the round-trip phase a reader reports shifts with the direction of
// the other end (the phase centre is not a point, and a patch's or a tag's pattern has a phase as well as a
// gain). Modelled as a low-order polynomial in the direction's azimuth and elevation in the element's own frame
// (boresight local +X, local Z up; rad):
//   φ_pattern(az, el) = Σ_{k=1..n} a_k·az^k + Σ_{k=1..m} e_k·el^k + c·az·el,  az = atan2(d_y, d_x), el = asin(d_z)
// No constant term: a constant is a per-carrier phase offset (ReaderParams::phase_offsets_rad). The same
// model is what `rfidray calibrate` fits, so a calibrated antenna is simulated as measured. Values only.
#include <cmath>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray {

struct PhasePattern {
  std::vector<double> azimuth_rad;    // a_1 … a_n: rad per rad^k
  std::vector<double> elevation_rad;  // e_1 … e_m
  double azimuth_elevation_rad = 0.0; // c: the cross term (rad per rad²)

  bool empty() const { return azimuth_rad.empty() && elevation_rad.empty() && azimuth_elevation_rad == 0.0; }
  // Round-trip phase (rad) toward `direction_local` (any length > 0, the element's frame).
  double phase_rad(const Vec3& direction_local) const {
    if (empty()) return 0.0;
    const Vec3 d = direction_local.normalized();
    const double az = std::atan2(d.y(), d.x());
    const double el = std::asin(std::clamp(d.z(), -1.0, 1.0));
    double out = 0.0, p = 1.0;
    for (double a : azimuth_rad) out += a * (p *= az);
    p = 1.0;
    for (double e : elevation_rad) out += e * (p *= el);
    return out + azimuth_elevation_rad * az * el;
  }
};

}  // namespace rfidray
