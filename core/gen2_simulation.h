#pragma once
// The Gen2 readers of a scenario (antennas with a `gen2` block, core/gen2_reader.h) run inventory rounds
// (core/gen2_inventory.h) on their ports instead of the tick model; simulate() calls simulate_gen2() for them.
//
// The channel decides who takes part and what is read:
//  - at each round's Query (after its Select), every present, selected tag is evaluated on the current port and
//    carrier at that instant: it is powered when the forward link reaches its chip (physical model:
//    P_tx·F·|h|² ≥ chip sensitivity; paper model: D ≤ range), and takes part when powered and its inventoried
//    flag equals the round's target; when its slot comes (T1 after the command) a tag that moved out of power
//    since leaves the round without replying (the same test at that instant; static links are not re-evaluated);
//  - a single (or captured) reply is read when read_tag() at the end of its EPC reply — antenna and tag where
//    they are then — says so (reader sensitivity, noise, read_probability): phase, RSSI, distance and the row's
//    time are those of that instant;
//  - inventoried flags (one session per reader; readers do not share tag flags): S0 reverts to A whenever the
//    tag is unpowered (and at every port switch and hop, when the carrier stops); S1 reverts s1_persistence_s
//    after it was set; S2/S3 revert after s23_persistence_s unpowered. Power is sampled at the Queries, so an
//    unpowered time is measured with the resolution of a round.
// Random streams: the slot draws of a reader's carrier period (from a start, port switch or hop to the next)
// from make_stream(seed, {"gen2", antenna, period}); a read's noise from make_stream(seed, {port antenna,
// k}) with k the port's k-th acknowledged reply — so results are identical at any thread count (readers run in
// parallel, each sequentially in time).
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"
#include "core/simulation.h"

namespace rfidray {

class TagCouplings;

// true for every antenna a Gen2 reader drives (its own and its ports). Throws InputError (with the scenario
// file and line) when an antenna is the port of two readers, a port has its own gen2 block, or a port's carriers
// differ from its reader's.
std::vector<bool> gen2_driven_antennas(const Scenario& scenario);

// Runs every Gen2 reader over [its antenna's start_s, duration_s]; writes the reads (time-ordered), ticks (slots),
// attempts (acknowledged replies) and gen2 slot statistics into result.antennas[port]. Throws InputError for a tag
// at an antenna (as the tick model does) or an invalid gen2 block.
void simulate_gen2(const Scenario& scenario, const SceneMotion& motion, const Channel& channel,
                   const TagCouplings& couplings, double duration_s, int threads, SimulationResult& result);

}  // namespace rfidray
