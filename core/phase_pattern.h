#pragma once
// Phase response of a real antenna or tag: the round-trip phase a reader reports shifts with the direction of
// the other end (the phase centre is not a point, and a patch's or a tag's pattern has a phase as well as a
// gain). Modelled as a low-order polynomial in the direction's azimuth and elevation in the element's own frame
// (boresight local +X, local Z up; rad):
//   φ_pattern(az, el) = Σ_{k=1..n} a_k·az^k + Σ_{k=1..m} e_k·el^k + c·az·el,  az = atan2(d_y, d_x), el = asin(d_z)
// No constant term: a constant is a per-carrier phase offset (ReaderParams::phase_offsets_rad). The same
// model is what `rfidray calibrate` fits, so a calibrated antenna is simulated as measured.
//
// Plus an optional ripple in azimuth, the part no low-order polynomial holds (a tag's own response, its
// coupling to what it is mounted on and next to — what real tags show and calibration cannot fit, README
// "Simulating a real reader"): φ_ripple(az) = Σ_n c_n cos(2n·az) + s_n sin(2n·az), harmonics of the half-space
// (period π). draw_phase_ripple() draws it at random: harmonics n = ⌈N/2⌉ … N, N = round(π / scale), so its
// wiggles are between one and two `scale`s long (a slower phase response is a pattern: the polynomial terms
// above, which calibration fits); c_n, s_n ~ N(0, σ²/count), σ log-normal about the median `rms` with log-sd
// `spread` per element: an RMS of σ over azimuth. Values only; draw_phase_ripple changes only its arguments.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/random.h"

namespace rfidray {

struct PhasePattern {
  std::vector<double> azimuth_rad;    // a_1 … a_n: rad per rad^k
  std::vector<double> elevation_rad;  // e_1 … e_m
  double azimuth_elevation_rad = 0.0; // c: the cross term (rad per rad²)
  std::vector<double> ripple_cos_rad, ripple_sin_rad;  // c_n, s_n of the ripple (equal sizes)
  double ripple_rms_rad = 0.0, ripple_scale_rad = 0.0, ripple_spread = 0.0;  // what it was drawn with (0: none)

  bool empty() const {
    return azimuth_rad.empty() && elevation_rad.empty() && azimuth_elevation_rad == 0.0 && ripple_cos_rad.empty();
  }
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
    for (size_t n = 0; n < ripple_cos_rad.size(); ++n)
      out += ripple_cos_rad[n] * std::cos(2.0 * (n + 1) * az) + ripple_sin_rad[n] * std::sin(2.0 * (n + 1) * az);
    return out + azimuth_elevation_rad * az * el;
  }
};

// Draws the ripple of `pattern` (replacing any): median RMS `rms_rad` over azimuth, log-sd `spread` of the RMS
// between elements, wiggles of `scale_rad`…2·`scale_rad` (rad). Deterministic for a given generator state.
void draw_phase_ripple(PhasePattern& pattern, double rms_rad, double scale_rad, double spread, Rng& rng);

}  // namespace rfidray
