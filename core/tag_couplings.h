#pragma once
// The tag couplings of a run (core/tag_antenna.h), resolved before the run's parallel loops: each tag's backing
// — the one the scenario gives, or the scene's nearest surface at the tag's first pose (a tag moves with what
// it is stuck on) — and its coupling at every carrier of every antenna.
//
// A moment-method solve takes a few milliseconds, so TagCouplingSolver solves each (antenna, surface, distance,
// frequency) once; distances are taken on a grid 0.5 % apart (the solve at the grid point nearest to the
// distance: the impedance changes by < 0.1 Ω over 0.25 % of a distance between 3 mm and 15 cm), so maps of many
// cells at slightly different distances share solves and the result does not depend on the order of queries.
//
// Thread-safety: TagCouplingSolver is not thread-safe (a memo); TagCouplings is immutable after construction
// and safe to read from any thread. Throws InputError (naming the tag) for unusable antenna or chip parameters.
#include <complex>
#include <map>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"
#include "core/tag_antenna.h"

namespace rfidray {

struct SceneMotion;

class TagCouplingSolver {
 public:
  // The backing of a tag at `pose`: kGiven and kNone as given; kScene becomes kScene with the nearest surface's
  // radio material and distance (within kSceneBackingSearch_m; metal or dielectric), or kNone when there is none.
  // `notes` (optional) collects lines for the user.
  TagBackingSpec resolve_backing(const TagParams& tag, const Pose& pose, const Channel& channel,
                             std::vector<std::string>* notes = nullptr);
  // The coupling of `tag` with its backing resolved to `backing`, at `frequency_hz`.
  TagCoupling coupling(const TagParams& tag, const TagBackingSpec& backing, double frequency_hz,
                       const std::string& field);
  size_t solves() const { return solves_; }

 private:
  std::complex<double> in_place(const TagAntennaSpec& antenna, const RadioMaterial* material, double distance_m,
                                double frequency_hz, const std::string& field);
  using Key = std::tuple<double, double, double, int, double, double, double, double>;
  std::map<Key, std::complex<double>> memo_;
  size_t solves_ = 0;
};

// Whether the infinite-plane detuning model describes a scene backing: the tag faces the facet (not beyond its
// edge) and the facet is at least as wide as the dipole. False: the detuning computed is an upper bound.
bool plane_backing_ok(const TagParams& tag, const TagBackingSpec& backing);

// The distance a solve is made at for a surface `distance_m` away (the 0.5 % grid above).
double coupling_grid_distance_m(double distance_m);

class TagCouplings {
 public:
  TagCouplings() = default;  // every tag a point tag
  // Resolves every tag with an antenna at its pose at its start time (motion.tags), for every antenna's carriers.
  TagCouplings(const Scenario& scenario, const SceneMotion& motion, const Channel& channel);
  // The same with each tag's pose given (index-aligned with scenario.tags), e.g. a live world's.
  TagCouplings(const Scenario& scenario, std::span<const Pose> tag_poses, const Channel& channel);

  bool empty() const { return offset_.empty(); }
  // The coupling of tag `tag` at carrier `hop` of antenna `antenna`; null for a point tag.
  const TagCoupling* at(size_t tag, size_t antenna, size_t hop) const {
    if (offset_.empty() || offset_[tag] < 0) return nullptr;
    return &values_[static_cast<size_t>(offset_[tag]) + hop_offset_[antenna] + hop];
  }
  // The backing each tag was resolved to (index-aligned with scenario.tags).
  const std::vector<TagBackingSpec>& backings() const { return backings_; }
  // What the scene backings found, for the user (one line per tag set of equal results at most).
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  std::vector<long> offset_;        // per tag: first value, −1 for a point tag
  std::vector<size_t> hop_offset_;  // per antenna: its carriers' first index within a tag's block
  std::vector<TagCoupling> values_;
  std::vector<TagBackingSpec> backings_;
  std::vector<std::string> notes_;
};

// The image path a kGiven backing adds to the one-way channel between the tag at `tag_pose` and an antenna at
// `antenna_position` (backing_image_factor with cosψ along the tag's local +X); 1 for other backings.
std::complex<double> backing_image_factor(const TagBackingSpec& backing, const Pose& tag_pose, const Vec3& antenna_position,
                                        double frequency_hz);

}  // namespace rfidray
