// `rfidray link`: one noise-free antenna–tag link in a scene — every path, the one-way channel h, the round-trip
// phase and the RSSI of the physical reader model, next to the ideal (free-space) channel. The tool to run when
// one tag reads badly.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "core/channel.h"
#include "core/error.h"
#include "core/level_validity.h"
#include "core/limits.h"
#include "core/reader.h"
#include "core/tag_couplings.h"
#include "core/units.h"
#include "raytrace/raytraced_channel.h"
#include "cli/commands.h"
#include "io/tag_antenna_spec.h"
#include "io/world_source.h"
#include "cli/number_list.h"

namespace rfidray::cli {
namespace {

Vec3 parse_vec3(const std::string& text, const std::string& option) {
  const auto v = parse_number_list(text, option);
  if (v.size() != 3) throw InputError("option " + option + ": expected X,Y,Z (got '" + clip(text) + "')");
  return Vec3(v[0], v[1], v[2]);
}

// linear:x,y,z | rhcp | lhcp (axis in the antenna's frame)
Polarization parse_polarization(const std::string& text, const std::string& option) {
  Polarization p;
  const auto colon = text.find(':');
  p.kind = parse_polarization_kind(text.substr(0, colon), option);
  if (p.kind == PolarizationKind::kLinear) {
    if (colon != std::string::npos) p.axis_local = parse_vec3(text.substr(colon + 1), option);
    // A direction: scaled by its largest component first, so 1e308,1e308,0 is (1, 1, 0)/√2 (its norm overflows).
    const double largest = p.axis_local.cwiseAbs().maxCoeff();
    if (!(largest > 0.0)) throw InputError("option " + option + ": linear axis must be non-zero");
    p.axis_local /= largest;
    p.axis_local.normalize();
  } else if (colon != std::string::npos) {
    throw InputError("option " + option + ": circular polarization takes no axis (got '" + clip(text) + "')");
  }
  return p;
}

// isotropic[:GAIN_DBI] | dipole | patch:GAIN_DBI[:BEAMWIDTH_DEG]
AntennaPattern parse_pattern(const std::string& text, const std::string& option) {
  const auto colon = text.find(':');
  AntennaPattern p;
  p.kind = parse_pattern_kind(text.substr(0, colon), option);
  if (p.kind == PatternKind::kTable) throw InputError("option " + option + ": table patterns come from a scenario file");
  std::vector<double> args;
  if (colon != std::string::npos) {
    std::string rest = text.substr(colon + 1);
    for (char& c : rest)
      if (c == ':') c = ',';
    args = parse_number_list(rest, option);
  }
  if (p.kind == PatternKind::kDipole && !args.empty()) throw InputError("option " + option + ": dipole takes no arguments");
  if (p.kind == PatternKind::kPatch && (args.empty() || args.size() > 2))
    throw InputError("option " + option + ": expected patch:GAIN_DBI[:BEAMWIDTH_DEG]");
  if (p.kind == PatternKind::kIsotropic && args.size() > 1) throw InputError("option " + option + ": expected isotropic[:GAIN_DBI]");
  if (!args.empty()) p.peak_gain_dbi = args[0];
  if (args.size() > 1) p.beamwidth_deg = args[1];
  try {
    p.validate(option);
  } catch (const InputError& e) {  // "field '--pattern.gain_dbi': …" → "option --pattern (gain_dbi): …"
    std::string msg = e.what();
    const std::string head = "field '" + option + ".";
    if (const size_t end = msg.find("': "); msg.rfind(head, 0) == 0 && end != std::string::npos)
      msg = "option " + option + " (" + msg.substr(head.size(), end - head.size()) + "): " + msg.substr(end + 3);
    throw InputError(msg);
  }
  return p;
}

// Roll, pitch, yaw in degrees (R = Rz(yaw)·Ry(pitch)·Rx(roll), the ROS convention).
Quat parse_rpy(const std::string& text, const std::string& option) {
  const Vec3 rpy = parse_vec3(text, option) * (kPi / 180.0);
  return Quat(Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
              Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()));
}

nlohmann::json complex_json(std::complex<double> c) { return {{"re", c.real()}, {"im", c.imag()}}; }

// The tag as an antenna (core/tag_antenna.h) on this link: its coupling and the image factor of a backing that is
// not in the scene (1 otherwise).
struct LinkTag {
  std::optional<TagCoupling> coupling;
  TagBackingSpec backing;
  std::complex<double> image_factor = 1.0;
};

// Noise-free physical reader model (core/reader_model.h): round-trip phase −arg(h²) − the tag's turn, the chip's
// P_tx·F·|h|² and the reader's P_tx·K·|h|⁴ (F = 1, K = modulation_factor for the point tag).
nlohmann::json channel_json(const Channel& channel, const Endpoint& antenna, const Endpoint& tag, double frequency_hz,
                            const ReaderParams& reader, const TagParams& tag_params, const LinkTag* link_tag = nullptr) {
  const std::vector<Path> paths = channel.paths(antenna, tag, frequency_hz);
  nlohmann::json jp = nlohmann::json::array();
  for (const Path& p : paths) {
    nlohmann::json one = {{"kind", to_string(p.kind)},
                          {"length_m", p.length_m},
                          {"point", {p.point.x(), p.point.y(), p.point.z()}},
                          {"material", p.material},
                          {"crossings", p.crossings},
                          {"coefficient", complex_json(p.coefficient)},
                          {"contribution", complex_json(p.contribution)}};
    // Every interaction point in order (reflection points, the diffraction point on the edge).
    nlohmann::json points = nlohmann::json::array();
    if (p.kind != PathKind::kLineOfSight) points.push_back({p.point.x(), p.point.y(), p.point.z()});
    if (p.kind == PathKind::kReflection2 || p.kind == PathKind::kDiffraction2) {
      points.push_back({p.point2.x(), p.point2.y(), p.point2.z()});
      one["material2"] = p.material2;
    }
    one["points"] = points;
    jp.push_back(one);
  }
  const TagCoupling* c = link_tag && link_tag->coupling ? &*link_tag->coupling : nullptr;
  // The tag's backing, when not meshed, adds its image path to every path (along the direct direction).
  const std::complex<double> h = sum_paths(paths) * (link_tag ? link_tag->image_factor : 1.0);
  const double gain2 = std::norm(h);
  const double chip_factor = c ? c->chip_power_factor : 1.0;
  const double k_mod = c ? c->modulation_factor : reader.modulation_factor;
  const double tag_turn = c ? c->backscatter_phase_rad : 0.0;
  nlohmann::json out = {{"channel", channel.name()}, {"paths", jp}, {"h", complex_json(h)}};
  if (gain2 > 0.0) {
    const double tag_dbm = reader.tx_power_dbm + linear_to_db(chip_factor * gain2);
    const double rssi = reader.tx_power_dbm + linear_to_db(k_mod) + 2.0 * linear_to_db(gain2);
    out["path_gain_db"] = linear_to_db(gain2);
    out["phase_rad"] = wrap_to_2pi(-std::arg(h * h) - tag_turn);
    out["rssi_dbm"] = rssi;
    out["tag_power_dbm"] = tag_dbm;
    out["tag_powered"] = tag_dbm >= tag_params.chip_sensitivity_dbm;
    out["readable"] = tag_dbm >= tag_params.chip_sensitivity_dbm && rssi >= reader.sensitivity_dbm;
  } else {  // no path at all: nothing to report rather than −inf
    out["path_gain_db"] = nullptr;
    out["phase_rad"] = nullptr;
    out["rssi_dbm"] = nullptr;
    out["tag_power_dbm"] = nullptr;
    out["tag_powered"] = false;
    out["readable"] = false;
  }
  return out;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

void print_table(const nlohmann::json& j) {
  std::printf("scene %s: %zu triangles, %zu facets; level %s; candidates %s; f = %.4f MHz\n",
              j["scene"]["files"].dump().c_str(), j["scene"]["triangles"].get<size_t>(),
              j["scene"]["facets"].get<size_t>(), j["level"].get<std::string>().c_str(),
              j["candidates"].get<std::string>().c_str(), j["frequency_hz"].get<double>() / 1e6);
  for (const auto& note : j["scene"]["notes"]) std::printf("note: %s\n", note.get<std::string>().c_str());
  if (j.contains("tag_antenna")) {
    const auto& t = j["tag_antenna"];
    const auto& m = t["backing"];
    const std::string backing = m["kind"] == "none" ? "free space"
                              : m["material"].get<std::string>() + " " + fmt("%.4g", m["distance_m"].get<double>()) +
                                    " m behind (" + m["kind"].get<std::string>() + ")";
    std::printf("tag antenna %s, chip %s, on %s: Z = %.3f %+.3fj Ω (free space %.3f %+.3fj), chip %.3f %+.3fj Ω, "
                "power transfer %.2f dB, chip power %+.2f dB, K = %.4g\n",
                t["antenna"].get<std::string>().c_str(), t["chip"].get<std::string>().c_str(), backing.c_str(),
                t["impedance_re_ohm"].get<double>(), t["impedance_im_ohm"].get<double>(),
                t["free_space_impedance_re_ohm"].get<double>(), t["free_space_impedance_im_ohm"].get<double>(),
                t["chip_impedance_re_ohm"].get<double>(), t["chip_impedance_im_ohm"].get<double>(),
                t["power_transfer_db"].get<double>(), t["chip_power_factor_db"].get<double>(),
                t["modulation_factor"].get<double>());
  }
  for (const char* which : {"raytraced", "ideal"}) {
    const auto& c = j[which];
    std::printf("\n%s (%s)\n", which, c["channel"].get<std::string>().c_str());
    std::printf("  %-2s %-10s %10s  %-26s %-12s %9s %8s %12s\n", "#", "kind", "length_m", "point", "material",
                "|coef|", "arg_deg", "power_db");
    int i = 0;
    for (const auto& p : c["paths"]) {
      const std::complex<double> co(p["coefficient"]["re"], p["coefficient"]["im"]);
      const std::complex<double> ct(p["contribution"]["re"], p["contribution"]["im"]);
      const auto& pt = p["point"];
      const std::string point = "(" + fmt("%.3f", pt[0]) + ", " + fmt("%.3f", pt[1]) + ", " + fmt("%.3f", pt[2]) + ")";
      std::printf("  %-2d %-10s %10.4f  %-26s %-12s %9.4f %8.2f %12s\n", i++, p["kind"].get<std::string>().c_str(),
                  p["length_m"].get<double>(), point.c_str(), p["material"].get<std::string>().c_str(), std::abs(co),
                  std::arg(co) * 180.0 / kPi, std::norm(ct) > 0 ? fmt("%.2f", linear_to_db(std::norm(ct))).c_str() : "-inf");
    }
    const std::complex<double> h(c["h"]["re"], c["h"]["im"]);
    if (c["phase_rad"].is_null()) {
      std::printf("  h = 0: no path reaches the tag\n");
    } else {
      std::printf("  h = %.6e %+.6ej  |h|² = %.2f dB  phase = %.4f rad  RSSI = %.2f dBm  tag power = %.2f dBm (%s)\n",
                  h.real(), h.imag(), c["path_gain_db"].get<double>(), c["phase_rad"].get<double>(),
                  c["rssi_dbm"].get<double>(), c["tag_power_dbm"].get<double>(),
                  c["readable"].get<bool>() ? "readable" : c["tag_powered"].get<bool>() ? "powered, reply too weak" : "not powered");
    }
  }
}

struct LinkOptions {
  std::vector<std::string> scene;
  std::string material, default_material, antenna, tag, antenna_pol = "linear:0,0,1", tag_pol = "linear:0,0,1";
  std::string pattern = "isotropic", tag_pattern = "isotropic", antenna_rpy = "0,0,0", tag_rpy = "0,0,0";
  std::string level = "single-bounce", candidates = "exact";
  double frequency_hz = ReaderParams{}.frequencies_hz.front();
  double tx_power_dbm = ReaderParams{}.tx_power_dbm;
  double thickness_m = -1.0;
  bool solid = false;  // --solid: every material's faces bound closed solids
  double drop_db = TraceOptions{}.drop_below_db;
  double thin_post_max_width_m = TraceOptions{}.thin_post_max_width_m;
  double double_diffraction_max_m = TraceOptions{}.double_diffraction_max_m;
  std::string tag_antenna, tag_chip = "matched", tag_backing;  // core/tag_antenna.h; "" = the point tag
  bool json = false;
  io::WorldSourceOptions world;  // --world instead of --scene
};

// --antenna / --tag: X,Y,Z, or with --world the name of one of its antennas (tags) at its world pose.
std::optional<Pose> named_pose(const std::string& text, const io::WorldSource* world, bool antenna) {
  if (!world || text.find(',') != std::string::npos) return std::nullopt;
  if (antenna) {
    for (const AntennaSpec& a : world->scenario.antennas)
      if (a.reader.name == text) return a.motion.pose;
  } else {
    for (const TagSpec& t : world->scenario.tags)
      if (t.tag.name == text) return t.motion.pose;
  }
  std::string known;
  if (antenna)
    for (const AntennaSpec& a : world->scenario.antennas) known += (known.empty() ? "" : ", ") + a.reader.name;
  else
    for (const TagSpec& t : world->scenario.tags) known += (known.empty() ? "" : ", ") + t.tag.name;
  throw InputError(std::string("option ") + (antenna ? "--antenna" : "--tag") + ": '" + text + "' is neither X,Y,Z nor " +
                   (antenna ? "an antenna" : "a tag") + " of the world (" + (known.empty() ? "none" : known) + ")");
}

// How far this link's level can be trusted (core/level_validity.h): the exact wedge at the nearer end's edge, and
// the difference to `full` computed on the same link (for a level below full).
nlohmann::json validity_json(const std::shared_ptr<const Scene>& scene, const TraceOptions& trace,
                             const RaytracedChannel& raytraced, const IdealChannel& ideal, const Endpoint& antenna,
                             const Endpoint& tag, double frequency_hz) {
  const std::complex<double> h = sum_paths(raytraced.paths(antenna, tag, frequency_hz));
  const double free = std::abs(sum_paths(ideal.paths(antenna, tag, frequency_hz)));
  const double relative = std::abs(h) / free;
  LevelValidity v = level_validity(trace.level, link_sight(raytraced, antenna, tag, frequency_hz),
                                   frequency_hz, relative);
  std::string reference = "the exact wedge series at the nearest edge";
  if (trace.level != ChannelLevel::kFull) {
    TraceOptions full_options = trace;
    full_options.level = ChannelLevel::kFull;
    const RaytracedChannel full(scene, full_options);
    const std::complex<double> h_full = sum_paths(full.paths(antenna, tag, frequency_hz));
    v = with_reference_error(v, std::abs(h - h_full) / free, relative, "full");
    reference = "the exact wedge series at the nearest edge and full on this link";
  }
  // No path at all: the level says the tag is dark, which FDTD shows is not so behind small obstacles (a 5 cm
  // upright leaves 0.25–0.62 of the free-space field behind it; docs/fullwave.md, "Other geometries").
  if (h == std::complex<double>(0.0)) {
    v.level_ok = false;
    v.reason += std::string(v.reason.empty() ? "" : "; ") +
                "no path reaches the tag at this level: its field there is not modelled (not necessarily zero)";
  }
  return {{"level_ok", v.level_ok},
          {"reason", v.reason},
          {"estimated_error", v.estimated_error},
          {"estimated_error_db", v.estimated_error_db},
          {"estimated_error_rad", v.estimated_error_rad},
          {"nearest_edge_m", v.nearest_edge_m ? nlohmann::json(*v.nearest_edge_m) : nlohmann::json(nullptr)},
          {"nearest_edge_krho", v.nearest_edge_krho},
          {"reference", reference}};
}

int run_link(const LinkOptions& o) {
  MaterialAssignment assignment;
  assignment.override_all = o.material;
  assignment.default_material = o.default_material;
  assignment.thickness_m = o.thickness_m;
  assignment.solid = o.solid;
  if (!o.material.empty()) find_radio_material(o.material, {}, "option --material");
  if (!o.default_material.empty()) find_radio_material(o.default_material, {}, "option --default-material");
  std::vector<std::filesystem::path> files(o.scene.begin(), o.scene.end());
  std::vector<std::string> warnings;
  std::optional<io::WorldSource> world;
  std::shared_ptr<const Scene> scene;
  if (!o.world.file.empty()) {
    if (!o.scene.empty()) throw InputError("give --scene FILE.obj or --world FILE, not both");
    if (!o.material.empty() || o.thickness_m >= 0.0 || o.solid)
      throw InputError("--world: materials come from --materials FILE (and --default-material), not "
                       "--material/--thickness/--solid");
    world = io::load_world_source(o.world, o.default_material);
    if (!o.json) std::fprintf(stderr, "rfidray: %s\n", world->summary.c_str());
    warnings = world->warnings;
    for (const auto& n : world->notes) std::cerr << "rfidray: note: " << n << "\n";
    scene = world->scene;
  } else {
    if (o.scene.empty()) throw InputError("give --scene FILE.obj (or --world FILE)");
    scene = load_scene(files, assignment, {}, &warnings);
  }
  for (const auto& w : extrapolation_warnings(*scene, o.frequency_hz)) warnings.push_back(w);
  for (const auto& w : warnings) std::cerr << "rfidray: warning: " << w << "\n";

  TraceOptions trace;
  trace.level = parse_channel_level(o.level, "--channel");
  if (!is_traced(trace.level))
    throw InputError("option --channel: '" + o.level + "' is not traced (link shows one of los, los+blocked, "
                     "single-bounce, double-bounce, full-selective, full; the ideal channel is printed beside it)");
  trace.candidates = parse_candidate_mode(o.candidates, "--candidates");
  if (!(o.drop_db >= 0.0 && o.drop_db <= 1000.0)) throw InputError("option --drop-db: must be in [0, 1000] dB");
  trace.drop_below_db = o.drop_db;
  limits::check_range(o.thin_post_max_width_m, 0.0, 1.0, "--thin-post-max-width", "m");
  trace.thin_post_max_width_m = o.thin_post_max_width_m;
  limits::check_range(o.double_diffraction_max_m, 0.0, 100.0, "--double-diffraction-max", "m");
  trace.double_diffraction_max_m = o.double_diffraction_max_m;
  limits::check_range(o.frequency_hz, limits::kMinFrequencyHz, limits::kMaxFrequencyHz, "--frequency", "Hz");
  limits::check_range(o.tx_power_dbm, -limits::kMaxPowerDbm, limits::kMaxPowerDbm, "--tx-power", "dBm");
  if (o.thickness_m >= 0.0) limits::check_range(o.thickness_m, 0.0, 100.0, "--thickness", "m");

  const io::WorldSource* w = world ? &*world : nullptr;
  // An end: a world's antenna or tag by name, or X,Y,Z with its own orientation; then polarization and pattern.
  auto endpoint = [&](const std::string& where, const std::string& rpy, const std::string& pol,
                      const std::string& pattern, bool is_antenna, const std::string& prefix,
                      const std::string& pattern_flag) {
    Endpoint e;
    if (auto p = named_pose(where, w, is_antenna)) {
      e.pose = *p;
    } else {
      e.pose.position = parse_vec3(where, "--" + prefix);
      for (int k = 0; k < 3; ++k)
        if (!limits::coordinate_ok(e.pose.position[k]))
          throw InputError("option --" + prefix + ": coordinates must be within ±" +
                           num(limits::kMaxCoordinateM) + " m (got '" + clip(where) + "')");
      e.pose.orientation = parse_rpy(rpy, "--" + prefix + "-rpy");
    }
    e.polarization = parse_polarization(pol, "--" + prefix + "-pol");
    e.pattern = parse_pattern(pattern, pattern_flag);
    return e;
  };
  const Endpoint antenna = endpoint(o.antenna, o.antenna_rpy, o.antenna_pol, o.pattern, true, "antenna", "--pattern");
  const Endpoint tag = endpoint(o.tag, o.tag_rpy, o.tag_pol, o.tag_pattern, false, "tag", "--tag-pattern");

  ReaderParams reader;
  reader.tx_power_dbm = o.tx_power_dbm;
  TagParams tag_params;
  const RaytracedChannel raytraced(scene, trace);
  const IdealChannel ideal;

  // The tag as an antenna: its coupling on the traced link (the ideal channel stays the paper's point tag).
  LinkTag link_tag;
  if (o.tag_antenna.empty() && (o.tag_chip != "matched" || !o.tag_backing.empty()))
    throw InputError("options --tag-chip and --tag-backing need --tag-antenna (dipole:LENGTH_M:RADIUS_M or table:FILE)");
  if (!o.tag_antenna.empty()) {
    tag_params.antenna = io::parse_tag_antenna(o.tag_antenna, "option --tag-antenna");
    tag_params.chip = io::parse_tag_chip(o.tag_chip, "option --tag-chip");
    tag_params.backing = io::parse_tag_backing(o.tag_backing.empty() ? "scene" : o.tag_backing, "option --tag-backing");
    validate(tag_params.antenna, tag_params.chip, tag_params.backing, "option --tag");
    TagCouplingSolver solver;
    std::vector<std::string> notes;
    link_tag.backing = solver.resolve_backing(tag_params, tag.pose, raytraced, &notes);
    for (const auto& n : notes) std::cerr << "rfidray: note: " << n << "\n";
    link_tag.coupling = solver.coupling(tag_params, link_tag.backing, o.frequency_hz, "option --tag");
    link_tag.image_factor = backing_image_factor(link_tag.backing, tag.pose, antenna.pose.position, o.frequency_hz);
  }

  nlohmann::json j;
  j["scene"] = {{"files", world ? std::vector<std::string>{o.world.file} : o.scene},
                {"triangles", scene->triangle_count()},
                {"facets", scene->facets().size()},
                {"notes", scene->notes()},
                {"warnings", warnings}};
  j["frequency_hz"] = o.frequency_hz;
  j["level"] = to_string(trace.level);
  j["candidates"] = to_string(trace.candidates);
  j["drop_below_db"] = trace.drop_below_db;
  j["antenna"] = {{"position", {antenna.pose.position.x(), antenna.pose.position.y(), antenna.pose.position.z()}},
                  {"polarization", o.antenna_pol}, {"pattern", o.pattern}};
  j["tag"] = {{"position", {tag.pose.position.x(), tag.pose.position.y(), tag.pose.position.z()}},
              {"polarization", o.tag_pol}, {"pattern", o.tag_pattern}};
  j["reader"] = {{"tx_power_dbm", reader.tx_power_dbm},
                 {"modulation_factor", reader.modulation_factor},
                 {"sensitivity_dbm", reader.sensitivity_dbm},
                 {"tag_chip_sensitivity_dbm", tag_params.chip_sensitivity_dbm}};
  if (link_tag.coupling) {
    const TagCoupling& c = *link_tag.coupling;
    const TagBackingSpec& m = link_tag.backing;
    j["tag_antenna"] = {
        {"antenna", o.tag_antenna},
        {"chip", o.tag_chip},
        {"impedance_re_ohm", c.antenna_impedance_ohm.real()},
        {"impedance_im_ohm", c.antenna_impedance_ohm.imag()},
        {"free_space_impedance_re_ohm", c.free_space_impedance_ohm.real()},
        {"free_space_impedance_im_ohm", c.free_space_impedance_ohm.imag()},
        {"chip_impedance_re_ohm", c.chip_impedance_ohm.real()},
        {"chip_impedance_im_ohm", c.chip_impedance_ohm.imag()},
        {"power_transfer", c.power_transfer},
        {"power_transfer_db", linear_to_db(c.power_transfer)},
        {"chip_power_factor_db", linear_to_db(c.chip_power_factor)},
        {"modulation_factor", c.modulation_factor},
        {"backscatter_phase_rad", c.backscatter_phase_rad},
        {"backing",
         {{"kind", m.kind == TagBackingSpec::Kind::kNone ? "none" : m.kind == TagBackingSpec::Kind::kGiven ? "given" : "scene"},
          {"material", m.material.name},
          {"perfect_conductor", m.material.perfect_conductor},
          // ε' − jσ/(ωε0) at this frequency; null for a perfect conductor.
          {"relative_permittivity", m.kind == TagBackingSpec::Kind::kNone || m.material.perfect_conductor
                                        ? nlohmann::json(nullptr)
                                        : complex_json(m.material.complex_permittivity(o.frequency_hz))},
          {"distance_m", m.distance_m},
          {"facet_extent_m", m.kind == TagBackingSpec::Kind::kScene && m.facet_extent_m < 1e299
                                 ? nlohmann::json(m.facet_extent_m) : nlohmann::json(nullptr)},
          // The detuning assumes an infinite plane: false when the facet is narrower than the dipole.
          {"faces_facet", m.faces_facet},
          {"plane_model_ok", plane_backing_ok(tag_params, m)}}},
        {"image_factor", complex_json(link_tag.image_factor)}};
  }
  j["raytraced"] = channel_json(raytraced, antenna, tag, o.frequency_hz, reader, tag_params, &link_tag);
  j["ideal"] = channel_json(ideal, antenna, tag, o.frequency_hz, reader, tag_params);
  j["validity"] = validity_json(scene, trace, raytraced, ideal, antenna, tag, o.frequency_hz);
  if (o.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    print_table(j);
    const auto& v = j["validity"];
    std::printf("validity: %s (estimated error %.2f of the free-space field)%s%s\n",
                v["level_ok"].get<bool>() ? "ok" : "OUTSIDE the level's validity", v["estimated_error"].get<double>(),
                v["reason"].get<std::string>().empty() ? "" : ": ", v["reason"].get<std::string>().c_str());
  }
  return 0;
}

}  // namespace

std::function<int()> setup_link(CLI::App& app) {
  auto o = std::make_shared<LinkOptions>();
  CLI::App* cmd = app.add_subcommand("link", "One noise-free antenna–tag link in a scene: paths, h, phase, RSSI (vs ideal)");
  cmd->add_option("--scene", o->scene, "OBJ scene file(s); usemtl names are radio materials (or --world)");
  add_world_options(*cmd, o->world);
  cmd->add_option("--material", o->material, "radio material for every surface (overrides usemtl)");
  cmd->add_option("--default-material", o->default_material, "radio material for usemtl names that are not materials");
  cmd->add_option("--thickness", o->thickness_m, "slab thickness (m) for every material (blocked paths, slab reflection)");
  cmd->add_flag("--solid", o->solid,
                "the scene's surfaces bound closed solids (walls as boxes): a direct path's entry and exit are one "
                "slab of the thickness they cut; reflection uses --thickness (docs/physics.md)");
  cmd->add_option("--antenna", o->antenna, "antenna position X,Y,Z (m), or with --world an antenna's name")->required();
  cmd->add_option("--tag", o->tag, "tag position X,Y,Z (m), or with --world a tag's name")->required();
  cmd->add_option("--frequency", o->frequency_hz, "carrier frequency (Hz)");
  cmd->add_option("--tx-power", o->tx_power_dbm, "reader transmit power (dBm)");
  cmd->add_option("--antenna-pol", o->antenna_pol, "linear:x,y,z | rhcp | lhcp (antenna frame)");
  cmd->add_option("--tag-pol", o->tag_pol, "linear:x,y,z | rhcp | lhcp (tag frame)");
  cmd->add_option("--pattern", o->pattern, "antenna pattern: isotropic[:GAIN_DBI] | dipole | patch:GAIN_DBI[:BW_DEG]");
  cmd->add_option("--tag-pattern", o->tag_pattern, "tag pattern, same syntax");
  cmd->add_option("--antenna-rpy", o->antenna_rpy, "antenna orientation roll,pitch,yaw (deg); boresight = local +X");
  cmd->add_option("--tag-rpy", o->tag_rpy, "tag orientation roll,pitch,yaw (deg)");
  add_channel_option_with_level_alias(*cmd, o->level, "los | los+blocked | single-bounce | double-bounce | full-selective | full");
  cmd->add_option("--candidates", o->candidates, "exact | exhaustive (reflection candidate search; fast = exact)");
  cmd->add_option("--drop-db", o->drop_db, "drop paths this many dB below the strongest");
  cmd->add_option("--thin-post-max-width", o->thin_post_max_width_m,
                  "full-selective, full: metal posts at most this wide (m) scatter as cylinders; 0 = as faces and edges");
  cmd->add_option("--double-diffraction-max", o->double_diffraction_max_m,
                  "full-selective, full: diffract twice between parallel edges at most this far apart (m); 0 = off");
  cmd->add_option("--tag-antenna", o->tag_antenna,
                  "the tag as an antenna: dipole:LENGTH_M:RADIUS_M[:CONDUCTIVITY_S_M] | table:FILE.csv (docs/tag-antenna.md)");
  cmd->add_option("--tag-chip", o->tag_chip, "matched[:DESIGN_HZ] | series:R_OHM:C_F | parallel:R_OHM:C_F (with --tag-antenna)");
  cmd->add_option("--tag-backing,--tag-mount", o->tag_backing,
                  "what the tag is on: scene (nearest meshed facet; default) | none | MATERIAL:DISTANCE_M, e.g. metal:0.01, "
                  "water:0.005 | dielectric:EPS_R:SIGMA_S_M:DISTANCE_M (a surface behind the tag, along its local -X)");
  cmd->add_flag("--json", o->json, "JSON output");
  return [o] { return run_link(*o); };
}

}  // namespace rfidray::cli
