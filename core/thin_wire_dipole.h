#pragma once
// Input impedance of a straight, centre-fed thin-wire dipole by the method of moments: the impedance of a tag
// antenna in free space and beside a surface parallel to its wire (core/tag_antenna.h uses it).
//
// Method. The mixed-potential electric-field integral equation on the wire (Harrington, "Field Computation by
// Moment Methods", 1968, ch. 4), solved by Galerkin's method: N equal segments, triangle basis and test
// functions centred on the N − 1 inner nodes (the current is zero at both ends), the vector potential of each
// triangle taken as that of its pulse, the scalar potential exact for the pulse charges the triangles carry.
// The wire's own interactions use the exact thin-wire kernel (the source current on the wire's surface,
// averaged around it; Wilton & Champagne, IEEE Trans. Antennas Propag. 40(10), 1992), so the solution
// converges as N grows past L/a instead of breaking down as the reduced kernel does. A delta-gap source at the
// centre node; Z = V / I(centre). The wire is symmetric about its centre, so only half of the currents are
// unknowns.
//
// Accuracy (measured, tests/core/test_thin_wire_dipole.cpp against nec2c): for the 0.166 m, 0.5 mm dipole at
// 866 MHz the free-space impedance is within 4 % of NEC-2's; beside a perfect conductor the power transfer to a
// chip is within 0.1 dB of NEC-2's from 3 mm to 20 cm. The reactance near resonance beside metal (5 mm–1 cm,
// |Z| of 1–10 Ω) depends on how the wire's ends and feed are discretised, in NEC-2 as here (NEC-2's own
// reactance at 1 cm moves by 1.8 Ω between 21 and 161 segments), so there |Z| agrees only to ~1 Ω.
//
// Units: metres, hertz, ohms. Thread-safe: pure functions of their arguments. Throws InputError (core/error.h)
// for a non-finite or non-positive length, radius or frequency, a radius not below a tenth of the length, or
// a negative conductivity.
#include <complex>
#include <memory>

namespace rfidray {

struct ThinWireDipole {
  double length_m = 0.0;  // tip to tip
  double radius_m = 0.0;
  // The wire's conductivity (S/m; 0: a perfect conductor). Its skin-effect surface impedance
  // Z_s = (1 + j)·√(ωμ0 / 2σ) per 2πa of circumference loads the wire (valid while a ≫ the skin depth, 2.7 µm in
  // aluminium at 866 MHz). Beside metal the radiation resistance falls below an ohm and this loss dominates.
  double conductivity_s_m = 0.0;
};

// What a surface parallel to the wire adds to the two potential kernels: ∫_{a1}^{a2} ∫_{b1}^{b2} g(z − z') dz' dz
// along the wire, with g normalised as the free-space kernel e^{−jkR}/(4πR) (so a perfect conductor's image
// is −e^{−jkR'}/(4πR'), R' measured to the image wire). `vector` is the vector potential's kernel (currents
// along the wire), `scalar` the scalar potential's (charges). Implementations are immutable after
// construction and so thread-safe.
class WireSurroundKernel {
 public:
  virtual ~WireSurroundKernel() = default;
  virtual std::complex<double> vector_integral(double a1, double a2, double b1, double b2) const = 0;
  virtual std::complex<double> scalar_integral(double a1, double a2, double b1, double b2) const = 0;
};

// A perfectly conducting plane parallel to the wire at `distance_m` from its axis (image theory: the image wire
// 2d away carries the reversed current and charge; exact for an infinite plane).
std::unique_ptr<WireSurroundKernel> perfect_conductor_plane(double distance_m, double frequency_hz);

// The input impedance (Ω) at `frequency_hz` in free space (`surround` null) or beside a surface. `segments`:
// 0 picks N from the wire's slenderness (segments about 1.5 radii long, 40 to 400), which the accuracy above
// was measured with; an explicit even N ≥ 4 is for convergence studies.
std::complex<double> dipole_input_impedance(const ThinWireDipole& dipole, double frequency_hz,
                                            const WireSurroundKernel* surround = nullptr, int segments = 0);

// The segment count `segments = 0` picks for this dipole.
int default_dipole_segments(const ThinWireDipole& dipole);

// ∫_{a1}^{a2} ∫_{b1}^{b2} e^{−jkR}/(4πR) dz' dz with R = √((z − z')² + b²): the reduced kernel at distance b
// from a line (b > 0). The building block of image kernels (a plane's image is such a line).
std::complex<double> line_kernel_integral(double a1, double a2, double b1, double b2, double b_m, double k_rad_m);

}  // namespace rfidray
