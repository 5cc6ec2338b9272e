#include "core/tag_couplings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/simulation.h"
#include "core/number_text.h"

namespace rfidray {
namespace {

constexpr double kGridStep = 0.005;  // relative spacing of the distance grid (0.5 %)

std::string metres(double v) { return rounded_text(v, 4); }

}  // namespace

bool plane_backing_ok(const TagParams& tag, const TagBackingSpec& backing) {
  if (backing.kind != TagBackingSpec::Kind::kScene) return true;
  if (!backing.faces_facet) return false;
  return !(tag.antenna.kind == TagAntennaSpec::Kind::kDipole && backing.facet_extent_m < tag.antenna.dipole.length_m);
}

double coupling_grid_distance_m(double distance_m) {
  return std::exp(std::round(std::log(distance_m) / kGridStep) * kGridStep);
}

TagBackingSpec TagCouplingSolver::resolve_backing(const TagParams& tag, const Pose& pose, const Channel& channel,
                                              std::vector<std::string>* notes) {
  if (tag.antenna.kind == TagAntennaSpec::Kind::kNone || tag.backing.kind != TagBackingSpec::Kind::kScene)
    return tag.backing;
  const auto s = channel.nearest_surface(pose.position, kSceneBackingSearch_m);
  TagBackingSpec m;
  if (!s) return m;  // kNone: nothing within reach (or no scene)
  m.kind = TagBackingSpec::Kind::kScene;
  m.material = s->material;
  m.distance_m = s->distance_m;
  m.facet_extent_m = s->facet_extent_m;
  m.faces_facet = s->faces_facet;
  if (tag.antenna.kind == TagAntennaSpec::Kind::kDipole && m.distance_m < tag.antenna.dipole.radius_m) {
    if (notes)
      notes->push_back("tag '" + tag.name + "': the nearest surface (" + s->material.name + ") is " + metres(s->distance_m) +
                       " m away, closer than the wire's radius; taken at the radius (" +
                       metres(tag.antenna.dipole.radius_m) + " m)");
    m.distance_m = tag.antenna.dipole.radius_m;
  }
  return m;
}

std::complex<double> TagCouplingSolver::in_place(const TagAntennaSpec& antenna, const RadioMaterial* material,
                                                 double distance_m, double frequency_hz, const std::string& field) {
  const double d = distance_m > 0.0 && material ? coupling_grid_distance_m(distance_m) : 0.0;
  // A surface is what its solve sees: a conductor, or a half-space of ε at this frequency.
  std::complex<double> eps = 0.0;
  int kind = 0;  // 0 free space, 1 conductor, 2 dielectric
  if (d > 0.0) {
    kind = material->perfect_conductor ? 1 : 2;
    if (kind == 2) eps = material->complex_permittivity(frequency_hz);
  }
  const Key key{antenna.dipole.length_m, antenna.dipole.radius_m, antenna.dipole.conductivity_s_m, kind,
                eps.real(), eps.imag(), d, frequency_hz};
  const auto it = memo_.find(key);
  if (it != memo_.end()) return it->second;
  ++solves_;
  const std::complex<double> z = antenna_impedance_in_place(antenna, d > 0.0 ? material : nullptr, d, frequency_hz, field);
  memo_.emplace(key, z);
  return z;
}

TagCoupling TagCouplingSolver::coupling(const TagParams& tag, const TagBackingSpec& backing, double frequency_hz,
                                        const std::string& field) {
  const TagAntennaSpec& a = tag.antenna;
  std::complex<double> z_free, z_in;
  if (a.kind == TagAntennaSpec::Kind::kDipole) {
    z_free = in_place(a, nullptr, 0.0, frequency_hz, field + ".antenna");
    z_in = backing.kind == TagBackingSpec::Kind::kNone
               ? z_free
               : in_place(a, &backing.material, backing.distance_m, frequency_hz, field + ".backing");
  } else {
    z_free = z_in = antenna_free_space_impedance(a, frequency_hz, field + ".antenna");
  }
  std::complex<double> z_chip;
  if (tag.chip.kind == TagChipSpec::Kind::kMatched && a.kind == TagAntennaSpec::Kind::kDipole) {
    const double f = tag.chip.design_frequency_hz > 0.0 ? tag.chip.design_frequency_hz : frequency_hz;
    z_chip = std::conj(in_place(a, nullptr, 0.0, f, field + ".chip"));
  } else {
    z_chip = chip_impedance(tag.chip, a, frequency_hz, field + ".chip");
  }
  if (!(z_free.real() > 0.0 && z_in.real() > 0.0 && z_chip.real() > 0.0))
    throw field_error(field, "the antenna's and the chip's resistances must be > 0");
  return tag_coupling(z_free, z_in, z_chip);
}

namespace {

std::vector<Pose> start_poses(const Scenario& scenario, const SceneMotion& motion) {
  std::vector<Pose> poses(scenario.tags.size());
  for (size_t i = 0; i < poses.size(); ++i)
    if (scenario.tags[i].tag.antenna.kind != TagAntennaSpec::Kind::kNone)
      poses[i] = motion.tags.at(i)->pose_at(scenario.tags[i].start_s);
  return poses;
}

}  // namespace

TagCouplings::TagCouplings(const Scenario& scenario, const SceneMotion& motion, const Channel& channel)
    : TagCouplings(scenario, start_poses(scenario, motion), channel) {}

TagCouplings::TagCouplings(const Scenario& scenario, std::span<const Pose> tag_poses, const Channel& channel) {
  const size_t n_tags = scenario.tags.size();
  bool any = false;
  for (const TagSpec& t : scenario.tags) any = any || t.tag.antenna.kind != TagAntennaSpec::Kind::kNone;
  if (!any) return;
  size_t per_tag = 0;
  for (const AntennaSpec& a : scenario.antennas) {
    hop_offset_.push_back(per_tag);
    per_tag += a.reader.frequencies_hz.size();
  }
  offset_.assign(n_tags, -1);
  backings_.resize(n_tags);
  TagCouplingSolver solver;
  size_t scene_backed = 0, narrow = 0, slabs = 0;
  double d_min = 1e300, d_max = 0.0;
  for (size_t i = 0; i < n_tags; ++i) {
    const TagSpec& spec = scenario.tags[i];
    backings_[i] = spec.tag.backing;
    if (spec.tag.antenna.kind == TagAntennaSpec::Kind::kNone) continue;
    backings_[i] = solver.resolve_backing(spec.tag, tag_poses[i], channel, &notes_);
    if (spec.tag.backing.kind == TagBackingSpec::Kind::kScene && backings_[i].kind == TagBackingSpec::Kind::kScene) {
      ++scene_backed;
      if (!plane_backing_ok(spec.tag, backings_[i])) ++narrow;
      if (backings_[i].material.thickness_m > 0.0) ++slabs;
      d_min = std::min(d_min, backings_[i].distance_m);
      d_max = std::max(d_max, backings_[i].distance_m);
    }
    offset_[i] = static_cast<long>(values_.size());
    const std::string field = "tag '" + spec.tag.name + "'";
    for (const AntennaSpec& a : scenario.antennas)
      for (double f : a.reader.frequencies_hz) values_.push_back(solver.coupling(spec.tag, backings_[i], f, field));
  }
  if (scene_backed > 0)
    notes_.push_back(std::to_string(scene_backed) + " tag(s) detuned by a surface found in the scene, " + metres(d_min) +
                     "–" + metres(d_max) + " m behind them (" + std::to_string(solver.solves()) +
                     " moment-method solves)");
  if (narrow > 0)
    notes_.push_back(std::to_string(narrow) + " of them beyond a facet's edge or on a facet narrower than the antenna "
                     "(e.g. a shelf's front edge): the detuning assumes an infinite plane, so for those it is an "
                     "upper bound");
  if (slabs > 0)
    notes_.push_back(std::to_string(slabs) + " tag(s) on a dielectric slab (a material with thickness_m): the detuning "
                     "is that of a half-space of its material, an upper bound for a thin wall");
}

std::complex<double> backing_image_factor(const TagBackingSpec& backing, const Pose& tag_pose, const Vec3& antenna_position,
                                        double frequency_hz) {
  if (backing.kind != TagBackingSpec::Kind::kGiven) return 1.0;
  const Vec3 to_antenna = antenna_position - tag_pose.position;
  const double len = to_antenna.norm();
  if (!(len > 0.0)) return 1.0;
  const Vec3 local = tag_pose.to_local_direction(to_antenna / len);
  return backing_image_factor(backing, local.x(), frequency_hz);
}

}  // namespace rfidray
