#pragma once
// Read coverage of a deployment: for each antenna of a scenario and each cell (a tag pose: a grid point, or a
// scenario tag), what a planner asks before installing anything — the probability of reading a tag there,
// its mean RSSI, the phase error multipath adds, and for a moving antenna the best localization a pass allows.
// The physics is the simulation's: the scenario's channel (Channel::one_way, the same call simulate makes),
// the antenna's phase centre, pattern and polarization, the tag's pattern and polarization, and the reader
// model's read rule (core/read_probability.h: noise, range perturbation, activation threshold, in closed form).
//
// Per antenna a (`ticks` below are the simulation's: t = k / update_rate, t ≥ start_s, up to the duration):
//  - fixed antenna (static trajectory): one attempt per carrier of the reader; read_probability, rssi_dbm and
//    phase_error_rad are averages over the carriers (each carrier used equally long);
//  - moving antenna (robot, waypoints, mast): a pass = every tick of the scenario (or every `stride` ticks, each
//    then standing for `stride` attempts): read_probability = 1 − Π(1 − p_k) ("read at least once per pass");
//    rssi_dbm and phase_error_rad are averages weighted by p_k; localization_bound_m is the Cramér–Rao bound of
//    the tag position from the pass's phase history (localization/cramer_rao.h; one phase offset per carrier,
//    σ² = noise_phi² + quantization step²/12 [+ receiver noise 1/(2·SNR)], reads weighted by p_k).
// rssi_dbm is the noise-free RSSI the model reports (physical: 10·log10(P_tx·K·|h|⁴ / 1 mW), as `rfidray link`;
// paper: 40·log10(G_RT·λ/(4πD))); for a fixed antenna it is given wherever a channel exists, even when the tag
// is not read (how far below the threshold it is), for a pass only where some tick may read; phase_error_rad is |wrap(arg h_ideal² − arg h²)| — the round-trip phase the scenario's channel
// adds against free space (the RMS over carriers / ticks), whatever the reader model. NaN marks "no value"
// (no channel: h = 0; no bound: fixed antenna or a non-identifiable position; a cell within 1 µm of the antenna).
// Deterministic (no random draws): the same numbers at any thread count and for any split of the cells.
// Thread-safe for distinct outputs; uses OpenMP inside: work items of 256 cells taken in spatial (Morton) order,
// the channel's own batch loops serial within each thread. Throws InputError on bad options.
#include <cstddef>
#include <functional>
#include <vector>

#include "core/channel.h"
#include "core/reader.h"
#include "core/scenario.h"
#include "core/simulation.h"

namespace rfidray::planning {

// Where coverage is evaluated: tag poses, each with its tag parameters (params[param_of[i]]).
struct CoverageCells {
  std::vector<Pose> poses;
  std::vector<TagParams> params{TagParams{}};
  std::vector<uint32_t> param_of;  // empty: every cell uses params[0]

  size_t size() const { return poses.size(); }
  const TagParams& tag(size_t i) const { return params[param_of.empty() ? 0 : param_of[i]]; }
  // The cells [first, first + count).
  CoverageCells slice(size_t first, size_t count) const;
};

struct CoverageOptions {
  double pass_step_s = 0.0;  // moving antennas: evaluate every this many seconds (0: every tick)
  bool height_known = true;  // localization bound in 2-D (x, y), the tag height known; else 3-D
  int threads = 0;           // OpenMP threads (0: default)
  bool information = false;  // also fill CoverageValues::information (for `place --objective worst-bound`)
  bool validity = true;      // fill CoverageValues::outside_validity, validity_error (NaN when false)
  // Called with the number of (cell × pose) link evaluations just finished; from any thread, may be empty.
  std::function<void(size_t)> progress;
};

// Values of one antenna, index-aligned with the cells.
struct CoverageValues {
  std::vector<double> read_probability, rssi_dbm, phase_error_rad, localization_bound_m;
  // Whether the channel's level can be trusted at the cell (core/level_validity.h: near metal edges and edge ends,
  // narrow obstacles, penetrable slabs, parallel plates), judged on the link from the antenna's first pose of the
  // pass (a fixed antenna's pose) at its first carrier, as `simulate` judges its tags at their start poses:
  // outside_validity 1 (outside) or 0, validity_error the estimated error (a fraction of the free-space field).
  // NaN for a channel that is not judged (ideal, or not a traced level) and where no value exists.
  std::vector<double> outside_validity, validity_error;
  // With CoverageOptions::information: 6 numbers per cell, the position information S of the pass packed as
  // localization::pack_information (m⁻²; zero for a fixed antenna, which fixes no position in this model).
  // Informations of several antennas add (localization/cramer_rao.h); position_bound_m(S) is
  // localization_bound_m. Empty otherwise.
  std::vector<double> information;
  void resize(size_t n, bool with_information = false);
};

// Link evaluations (cell × pose × carrier) coverage() makes for antenna `a` — the unit of `progress`.
size_t coverage_work(const Scenario& scenario, const SceneMotion& motion, size_t antenna, size_t cells,
                     const CoverageOptions& options);

// The cells of one of coverage()'s work items (the threads take items in turn): at most 256, a compact Morton
// patch whose rays share the BVH's warm parts; on a small map few enough that each thread gets about four items
// (one item of 256 ran a 200-cell map on one thread, and 400 cells as 256 + 144 left one of two threads idle a
// third of the time); at least 64 and a multiple of 16, since a batch shares its plane and edge pairs over blocks
// of 16 tags from 64 tags on (raytrace/path_finder.h). A map under 64 cells, where no item shares, is one item per
// thread (it ran on one thread). The results do not depend on it.
size_t coverage_cells_per_item(size_t cells, int threads);

// Coverage of antenna `antenna` of the scenario over `cells`. `motion` is build_motion(scenario); `channel` the
// scenario's channel (make_channel); `ideal` the free-space reference for the phase error (pass the same
// object as `channel` when the scenario's channel is ideal).
CoverageValues coverage(const Scenario& scenario, const SceneMotion& motion, size_t antenna, const Channel& channel,
                        const Channel& ideal, const CoverageCells& cells, const CoverageOptions& options = {});

}  // namespace rfidray::planning
