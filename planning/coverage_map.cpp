#include "planning/coverage_map.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <tuple>

#include "core/error.h"
#include "core/level_validity.h"
#include "core/limits.h"
#include "core/read_probability.h"
#include "core/tag_couplings.h"
#include "core/units.h"
#include "localization/cramer_rao.h"
#include "raytrace/morton.h"

namespace rfidray::planning {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The cells in spatial (Morton) order, index order on ties: a work item's cells are then a compact patch rather
// than a strip of a grid row, so its rays run through the same part of the BVH (warm caches). Every cell is
// computed on its own, so the order changes nothing but speed.
std::vector<uint32_t> spatial_order(const CoverageCells& cells) {
  std::vector<std::pair<uint64_t, uint32_t>> keyed(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) keyed[i] = {morton_key(cells.poses[i].position), static_cast<uint32_t>(i)};
  std::sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> order(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) order[i] = keyed[i].second;
  return order;
}

// One antenna pose the coverage is evaluated at.
struct PassPose {
  Pose centre;          // phase centre
  size_t carrier = 0;   // index into the reader's frequencies
  double weight = 1.0;  // attempts this pose stands for
};

struct Pass {
  bool moving = false;
  std::vector<PassPose> poses;
};

Pass antenna_pass(const Scenario& scenario, const SceneMotion& motion, size_t a, const CoverageOptions& options) {
  const AntennaSpec& ant = scenario.antennas.at(a);
  const ReaderParams& reader = ant.reader;
  Pass pass;
  const TrajectoryPtr& traj = motion.antennas.at(a);
  if (traj->is_static()) {
    const Pose centre = phase_centre_pose(reader, traj->pose_at(ant.start_s));
    for (size_t c = 0; c < reader.frequencies_hz.size(); ++c) pass.poses.push_back({centre, c, 1.0});
    return pass;
  }
  pass.moving = true;
  if (!(std::isfinite(options.pass_step_s) && options.pass_step_s >= 0.0))
    throw InputError("pass step must be finite and >= 0 s (got " + std::to_string(options.pass_step_s) + ")");
  const double duration = scenario_duration_s(scenario, motion);
  const double rate = reader.update_rate_hz;
  // The simulation's ticks: t = k / rate, k = 0 … ⌊duration·rate⌋ (core/simulation.cpp).
  const double ticks = std::floor(duration * rate + 1e-9) + 1.0;
  if (!(ticks <= limits::kMaxTicks))
    throw InputError("antenna '" + reader.name + "': the pass has more than 1e9 ticks");
  const uint64_t n_ticks = static_cast<uint64_t>(ticks);
  const uint64_t stride = options.pass_step_s > 0.0
                              ? std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(options.pass_step_s * rate)))
                              : 1;
  for (uint64_t k = 0; k < n_ticks; k += stride) {
    const double t = static_cast<double>(k) / rate;
    if (t < ant.start_s) continue;
    pass.poses.push_back({phase_centre_pose(reader, traj->pose_at(t)), hop_index_at(reader, t),
                          static_cast<double>(std::min(stride, n_ticks - k))});
  }
  return pass;
}

// Phase noise σ of one read (rad): the reader's n_φ, the quantization (uniform, step²/12) and, for the physical
// model with receiver noise, 1/(2·SNR) (core/reader.h).
double phase_sigma(const ReaderParams& reader, double p_rx_w) {
  double var = reader.noise_phi_rad * reader.noise_phi_rad;
  if (reader.phase_bits > 0) {
    const double step = kTwoPi / std::ldexp(1.0, reader.phase_bits);
    var += step * step / 12.0;
  }
  if (reader.model == ReaderModelKind::kPhysical && reader.snr_at_sensitivity_db > 0.0 && p_rx_w > 0.0)
    var += 0.5 / (std::pow(10.0, reader.snr_at_sensitivity_db / 10.0) * p_rx_w / dbm_to_watt(reader.sensitivity_dbm));
  return std::sqrt(var);
}

}  // namespace

CoverageCells CoverageCells::slice(size_t first, size_t count) const {
  CoverageCells out;
  out.params = params;
  first = std::min(first, poses.size());
  count = std::min(count, poses.size() - first);
  out.poses.assign(poses.begin() + static_cast<std::ptrdiff_t>(first),
                   poses.begin() + static_cast<std::ptrdiff_t>(first + count));
  if (!param_of.empty())
    out.param_of.assign(param_of.begin() + static_cast<std::ptrdiff_t>(first),
                        param_of.begin() + static_cast<std::ptrdiff_t>(first + count));
  return out;
}

void CoverageValues::resize(size_t n, bool with_information) {
  read_probability.assign(n, kNaN);
  rssi_dbm.assign(n, kNaN);
  phase_error_rad.assign(n, kNaN);
  localization_bound_m.assign(n, kNaN);
  outside_validity.assign(n, kNaN);
  validity_error.assign(n, kNaN);
  information.assign(with_information ? 6 * n : 0, 0.0);
}

size_t coverage_work(const Scenario& scenario, const SceneMotion& motion, size_t antenna, size_t cells,
                     const CoverageOptions& options) {
  return antenna_pass(scenario, motion, antenna, options).poses.size() * cells;
}

size_t coverage_cells_per_item(size_t cells, int threads) {
  constexpr size_t kMost = 256, kLeast = 64, kItemsPerThread = 4;
  const size_t thread_count = static_cast<size_t>(std::max(threads, 1));
  // A map under 64 cells shares no pairs in any item (raytrace/path_finder.h: from 64 tags on): one item per thread.
  // (From 64 cells on, a 64-cell item that shares beats splitting it: 120 cells as 60 + 60 took 1.08× the time of
  // 64 + 56 on 2 threads; bench/results/planning/.)
  if (cells < kLeast) return std::max<size_t>(1, (cells + thread_count - 1) / thread_count);
  const size_t lanes = kItemsPerThread * thread_count;
  const size_t wanted = (cells + lanes - 1) / lanes;
  return std::clamp((wanted + 15) / 16 * 16, kLeast, kMost);
}

CoverageValues coverage(const Scenario& scenario, const SceneMotion& motion, size_t antenna, const Channel& channel,
                        const Channel& ideal, const CoverageCells& cells, const CoverageOptions& options) {
  const ReaderParams& reader = scenario.antennas.at(antenna).reader;
  const Pass pass = antenna_pass(scenario, motion, antenna, options);
  const bool physical = reader.model == ReaderModelKind::kPhysical;
  const bool same_channel = &channel == &ideal;
  const Endpoint antenna_shape{Pose{}, reader.pattern, reader.polarization};
  const double p_tx_w = dbm_to_watt(reader.tx_power_dbm);
  const double total_carrier_weight = static_cast<double>(reader.frequencies_hz.size());

  const size_t n = cells.size();
  CoverageValues out;
  out.resize(n, options.information);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const size_t chunk_cells = coverage_cells_per_item(n, threads);
  const size_t n_chunks = (n + chunk_cells - 1) / chunk_cells;
  std::exception_ptr error;
  std::mutex error_mutex;

  const std::vector<uint32_t> order = spatial_order(cells);
  // The level judged at each cell, from the pass's first pose (CoverageValues::outside_validity).
  const std::optional<ChannelLevel> judged = options.validity ? judged_level(channel) : std::nullopt;

  // Tag antennas (core/tag_couplings.h): each cell's backing (the scene's metal near the cell, or the given one) and
  // its coupling at every carrier, resolved serially before the parallel loop. Cells share a block when their tag
  // parameters and resolved backing are the same (distances on the solver's 0.5 % grid), so a map of a million
  // cells holds a few hundred blocks.
  const size_t n_carriers = reader.frequencies_hz.size();
  std::vector<TagCoupling> coupling_blocks;  // n_carriers per block
  std::vector<TagBackingSpec> block_backing;
  std::vector<uint32_t> block_of;            // per cell; kNoBlock: a point tag
  constexpr uint32_t kNoBlock = std::numeric_limits<uint32_t>::max();
  bool any_antenna = false;
  for (const TagParams& t : cells.params) any_antenna = any_antenna || t.antenna.kind != TagAntennaSpec::Kind::kNone;
  if (any_antenna) {
    TagCouplingSolver solver;
    std::map<std::tuple<size_t, int, std::string, double>, uint32_t> block_index;
    block_of.assign(n, kNoBlock);
    for (size_t k = 0; k < n; ++k) {
      const size_t param = cells.param_of.empty() ? 0 : cells.param_of[k];
      const TagParams& t = cells.params[param];
      if (t.antenna.kind == TagAntennaSpec::Kind::kNone) continue;
      const TagBackingSpec backing = solver.resolve_backing(t, cells.poses[k], channel);
      const double d = backing.kind == TagBackingSpec::Kind::kNone ? 0.0 : coupling_grid_distance_m(backing.distance_m);
      const auto key = std::make_tuple(param, static_cast<int>(backing.kind), backing.material.name, d);
      auto it = block_index.find(key);
      if (it == block_index.end()) {
        it = block_index.emplace(key, static_cast<uint32_t>(block_backing.size())).first;
        block_backing.push_back(backing);
        for (double f : reader.frequencies_hz)
          coupling_blocks.push_back(solver.coupling(t, backing, f, "coverage cell tag '" + t.name + "'"));
      }
      block_of[k] = it->second;
    }
  }

#pragma omp parallel num_threads(threads)
  {
    // The cells are the parallel work: the channel's own loops over a batch stay serial in each thread (else
    // with one thread per process, e.g. MPI ranks × 1 thread, they would start threads of their own).
    omp_set_num_threads(1);
#pragma omp for schedule(dynamic, 1)
    for (size_t chunk = 0; chunk < n_chunks; ++chunk) {
      try {
        const size_t c0 = chunk * chunk_cells, c1 = std::min(n, c0 + chunk_cells), m = c1 - c0;
        const uint32_t* cell_of = &order[c0];  // the chunk's i-th cell
        std::vector<Endpoint> tags(m);
        for (size_t i = 0; i < m; ++i) {
          const TagParams& t = cells.tag(cell_of[i]);
          tags[i] = Endpoint{cells.poses[cell_of[i]], t.pattern, t.polarization};
        }
        std::vector<std::complex<double>> h(m), h_ideal(m);
        std::vector<double> miss_log(m, 0.0), sum_p(m, 0.0), sum_rssi(m, 0.0), w_rssi(m, 0.0), sum_e2(m, 0.0),
            w_e(m, 0.0);
        std::vector<char> valid(m, 1), certain(m, 0);
        std::vector<localization::PhaseFisher> fisher;
        if (pass.moving)
          for (size_t i = 0; i < m; ++i) fisher.emplace_back(cells.poses[cell_of[i]].position);
        for (const PassPose& pp : pass.poses) {
          const double f = reader.frequencies_hz[pp.carrier];
          const double lambda = wavelength_m(f);
          Endpoint ant = antenna_shape;
          ant.pose = pp.centre;
          channel.one_way(ant, tags, f, h);
          if (!same_channel) ideal.one_way(ant, tags, f, h_ideal);
          for (size_t i = 0; i < m; ++i) {
            if (!valid[i]) continue;
            const double d = (tags[i].pose.position - pp.centre.position).norm();
            if (!(d >= kMinLinkDistance_m)) {
              valid[i] = 0;
              continue;
            }
            LinkState link;
            link.distance_m = d;
            link.frequency_hz = f;
            link.hop_index = pp.carrier;
            if (!block_of.empty() && block_of[cell_of[i]] != kNoBlock) {
              const uint32_t b = block_of[cell_of[i]];
              link.tag_coupling = &coupling_blocks[b * n_carriers + pp.carrier];
              h[i] *= backing_image_factor(block_backing[b], tags[i].pose, pp.centre.position, f);
            }
            link.h_one_way = h[i];
            const double p = read_probability(reader, cells.tag(cell_of[i]), link);
            const double gain2 = std::norm(h[i]);
            const double k_mod = link.tag_coupling ? link.tag_coupling->modulation_factor : reader.modulation_factor;
            double rssi = kNaN, p_rx_w = 0.0;
            if (physical) {
              if (gain2 > 0.0) {
                p_rx_w = p_tx_w * k_mod * gain2 * gain2;
                rssi = reader.tx_power_dbm + linear_to_db(k_mod) + 2.0 * linear_to_db(gain2);
              }
            } else {
              rssi = 40.0 * std::log10(reader.communication_gain * lambda / (4.0 * kPi * d));
            }
            double err = kNaN;
            if (gain2 > 0.0) {
              const std::complex<double> hi = same_channel ? h[i] : h_ideal[i];
              err = std::abs(wrap_to_pi(std::arg(hi * hi) - std::arg(h[i] * h[i])));
            }
            // Averages: a fixed antenna over its carriers (weight 1 each); a pass weighted by the expected reads.
            const double w = pass.moving ? pp.weight * p : 1.0;
            sum_p[i] += p;
            if (pass.moving) {
              if (p >= 1.0)
                certain[i] = 1;
              else
                miss_log[i] += pp.weight * std::log1p(-p);
            }
            if (std::isfinite(rssi) && w > 0.0) sum_rssi[i] += w * rssi, w_rssi[i] += w;
            if (std::isfinite(err) && w > 0.0) sum_e2[i] += w * err * err, w_e[i] += w;
            if (pass.moving && p > 0.0 && gain2 >= 0.0)
              fisher[i].add({pp.centre.position, lambda, pp.carrier, pp.weight * p, phase_sigma(reader, p_rx_w)});
          }
          if (options.progress) options.progress(m);
        }
        if (judged && !pass.poses.empty()) {
          Endpoint ant = antenna_shape;
          ant.pose = pass.poses.front().centre;
          const double f = reader.frequencies_hz[pass.poses.front().carrier];
          for (size_t i = 0; i < m; ++i) {
            if (!valid[i]) continue;
            const LevelValidity v = level_validity(*judged, link_sight(channel, ant, tags[i], f), f);
            out.outside_validity[cell_of[i]] = v.level_ok ? 0.0 : 1.0;
            out.validity_error[cell_of[i]] = v.estimated_error;
          }
        }
        for (size_t i = 0; i < m; ++i) {
          if (!valid[i]) continue;
          const size_t k = cell_of[i];
          out.read_probability[k] =
              pass.moving ? (certain[i] ? 1.0 : -std::expm1(miss_log[i])) : sum_p[i] / total_carrier_weight;
          if (w_rssi[i] > 0.0) out.rssi_dbm[k] = sum_rssi[i] / w_rssi[i];
          if (w_e[i] > 0.0) out.phase_error_rad[k] = std::sqrt(sum_e2[i] / w_e[i]);
          if (pass.moving) {
            const Eigen::Matrix3d info = fisher[i].information();
            if (auto b = localization::position_bound_m(info, options.height_known)) out.localization_bound_m[k] = *b;
            if (options.information) {
              const std::array<double, 6> packed = localization::pack_information(info);
              std::copy(packed.begin(), packed.end(), out.information.begin() + static_cast<std::ptrdiff_t>(6 * k));
            }
          }
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  }
  if (error) std::rethrow_exception(error);
  return out;
}

}  // namespace rfidray::planning
