#pragma once
// The Cramér–Rao bound of a tag's position from the phase history an antenna pass would produce: what no unbiased
// estimator (localization/methods.h) can beat with those reads. Used by coverage maps to predict, before a run,
// how well a robot pass localizes each tag.
//
// Model (the paper's eq. 3 with one offset per carrier group): φ_i = φ0_g(i) + 4π·|a_i − θ|/λ_i + n_i,
// n_i ~ N(0, σ_i²) independent, θ the tag position, a_i the antenna's phase centre. Each observation counts with
// weight w_i, the expected number of reads at that pose (its read probability). Fisher information
//   J = Σ_i w_i/σ_i² · g_i g_iᵀ,  g_i = [∂φ_i/∂θ ; e_g(i)],  ∂φ_i/∂θ = (4π/λ_i)·(θ − a_i)/|θ − a_i|.
// The offsets are nuisance parameters: the position block of J⁻¹ is the inverse of the Schur complement
//   S = J_θθ − Σ_g J_θg J_θgᵀ / J_gg  (J_gg is diagonal: each offset enters only its group).
// The bound returned is √trace(S⁻¹), the RMS position error (m) of an efficient estimator (Kay, Fundamentals of
// Statistical Signal Processing I, 1993, §3.7). It is local: it knows nothing of the mirror ambiguity of a
// straight pass or of unwrapping errors, and the multipath bias is not in it.
// Thread-safe (pure). Returns nullopt when the position is not identifiable (S singular: too few reads, or an
// aperture that constrains only some directions, e.g. a 3-D fit from a straight pass).
//
// S is the position information of a pass once its offsets are eliminated. Passes with offsets of their own
// (other antennas, each with its own cable and carrier offsets) are independent given θ, so their
// informations add: the joint bound of several antennas is position_bound_m(S_1 + S_2 + …) (what
// `rfidray place --objective worst-bound` minimises).
#include <optional>
#include <span>

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/geometry.h"

namespace rfidray::localization {

struct PhaseObservation {
  Vec3 antenna_m = Vec3::Zero();  // phase centre of the antenna at this read
  double wavelength_m = 0.0;
  size_t offset_group = 0;        // observations of one group share one unknown phase offset (e.g. per carrier)
  double weight = 1.0;            // expected reads at this pose (read probability), ≥ 0
  double sigma_rad = 0.1;         // phase noise σ, > 0
};

// The Fisher information of one tag, accumulated observation by observation (a pass of thousands of reads needs
// no list of them). Groups are kept in a small sorted array; add() order does not change the result beyond
// floating-point summation order, which is the caller's (fixed) order.
class PhaseFisher {
 public:
  explicit PhaseFisher(const Vec3& tag) : tag_(tag) {}
  void add(const PhaseObservation& o);
  // height_known: θ = (x, y) with z fixed at the tag's (as `localize --height-known`); else θ = (x, y, z).
  std::optional<double> bound_m(bool height_known) const;
  // The position information S (3 × 3, symmetric, m⁻²): Σ over groups of the weighted gradient scatter.
  Eigen::Matrix3d information() const;

 private:
  // Per group, the weighted scatter of the gradients about their weighted mean, updated one observation at a
  // time (West 1979, the weighted form of Welford's update): Σ w (g − ḡ)(g − ḡ)ᵀ is that group's share of the
  // Schur complement S, without the cancellation of J_θθ − J_θg J_θgᵀ / J_gg.
  struct Group {
    size_t id = 0;
    double weight = 0.0;
    Vec3 mean = Vec3::Zero();
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  };
  Vec3 tag_;
  std::vector<Group> groups_;
};

// √trace(S⁻¹) of the position block of an information matrix S (m⁻²): (x, y) when height_known, else
// (x, y, z); nullopt when not identifiable (the smallest eigenvalue of the block ≤ 1e-9 × the largest).
std::optional<double> position_bound_m(const Eigen::Matrix3d& information, bool height_known);

// S packed as its upper triangle (xx, xy, xz, yy, yz, zz), and back — how coverage maps pass it on.
std::array<double, 6> pack_information(const Eigen::Matrix3d& s);
Eigen::Matrix3d unpack_information(const double* packed);

// The same from a list of observations.
std::optional<double> phase_position_crb_m(const Vec3& tag, std::span<const PhaseObservation> observations,
                                           bool height_known);

}  // namespace rfidray::localization
