#pragma once
// One Gen2 inventory round, the tags' side and the reader's (EPC UHF Gen2 v1.2.0 §6.3.2.8–6.3.2.11, Annex D),
// without a channel: the channel enters through RoundHooks (who is decoded, how strong a reply is).
//  - Query(Q): every participating tag draws its slot counter uniformly in [0, 2^Q − 1] (§6.3.2.4.8);
//  - QueryRep: counters decrement, a tag whose counter is 0 replies (RN16);
//  - one reply: ACK, the tag backscatters PC + EPC + CRC-16, and leaves the round (its inventoried flag flips);
//  - several replies: lost, unless capture is on and the strongest exceeds the sum of the others by the capture
//    ratio; tags that replied but were not acknowledged wait with counter 7FFFh (§6.3.2.4.8: 0000h decrements to
//    7FFFh) until a QueryAdjust or the next Query redraws them;
//  - fixed Q: a frame of 2^Q slots (Query + 2^Q − 1 QueryReps), framed slotted ALOHA;
//  - Q algorithm (Annex D, Figure D.1): Q_fp starts at `start_q` (the caller's population estimate,
//    gen2_start_q; Annex D leaves the start to the reader); an empty slot Q_fp = max(0, Q_fp − C), a
//    collided one Q_fp = min(15, Q_fp + C), a single one unchanged; Q = round(Q_fp); when Q changes the next
//    command is a QueryAdjust (every tag still in the round redraws), else a QueryRep. The round ends at an empty
//    slot with Q = 0 (every tag left would have replied).
// Slot air times are those of core/gen2_link_timing.h. Not thread-safe per object (one per reader thread); the
// draws come from the caller's Rng in a fixed order (one per tag at Query / QueryAdjust, in participant order).
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "core/gen2_link_timing.h"
#include "core/gen2_reader.h"
#include "core/random.h"

namespace rfidray {

struct Gen2SlotStats {
  uint64_t rounds = 0;
  uint64_t empty = 0, single = 0, collided = 0;  // slots by how many tags replied: 0, 1, more
  uint64_t captured = 0;                          // collided slots in which the strongest reply was decoded
  uint64_t reads = 0;                             // EPCs decoded
  double air_time_s = 0.0;                        // Selects + slots
  void add(const Gen2SlotStats& o);
  uint64_t slots() const { return empty + single + collided; }
};

// The tags' slot counters of one round. Reused across rounds (no allocation once grown).
class Gen2Round {
 public:
  void begin(std::span<const uint32_t> participants, int q, Rng& rng);
  void query_adjust(int q, Rng& rng);  // every tag still in the round draws again
  void query_rep() { ++current_; }
  // Tags whose counter is 0 in the current slot, in participant order. A tag for which `powered` (if set) is
  // false has lost power: it leaves the round without replying.
  std::span<const uint32_t> replies(const std::function<bool(uint32_t)>& powered = {});
  // After a slot: `acknowledged` leaves the round; every other tag that replied waits for a QueryAdjust.
  void close_slot(std::optional<uint32_t> acknowledged);
  size_t remaining() const { return ids_.size(); }

 private:
  void draw(int q, Rng& rng);
  std::vector<uint32_t> ids_;
  std::vector<uint64_t> slot_;  // absolute slot index; kWaiting when out until redrawn
  std::vector<uint32_t> replies_;
  std::vector<size_t> reply_pos_;
  uint64_t current_ = 0;
};

// What the channel decides, for run_gen2_round.
struct Gen2RoundHooks {
  // A reply that is alone (or captured) was acknowledged; its EPC reply ends at `epc_end_s`. Return true when
  // the reader decodes it (the read is then the caller's to record).
  std::function<bool(uint32_t tag, double epc_end_s)> read;
  // Whether a tag whose counter reached 0 is still powered when it would reply (`t_s`: the slot's reply time);
  // unset: always. A tag that is not leaves the round (it lost its state with its power).
  std::function<bool(uint32_t tag, double t_s)> powered;
  // Backscattered power (W) of a tag's reply; called only with a capture ratio, for tags in collided slots.
  std::function<double(uint32_t tag)> reply_power_w;
};

// Runs one round from t_s (its Query starts then): the slots are played until the round ends, or until a slot
// would start at or after stop_s (the port's dwell or the carrier ends). Returns the time the round's last slot
// ended. Adds to `stats` (rounds, slots, air time; reads when hooks.read says so). `participants`: the tags
// that take part (powered, flag = target, selected).
// `start_q`: the Q of the Query with the Q algorithm (a fixed Q uses spec.q).
double run_gen2_round(const Gen2ReaderSpec& spec, const Gen2LinkTiming& timing, std::span<const uint32_t> participants,
                      double t_s, double stop_s, Rng& rng, Gen2Round& round, Gen2SlotStats& stats,
                      const Gen2RoundHooks& hooks, int start_q);

// The Q algorithm's starting Q for the next round: spec.q for the first round, then round(log2 n) of the n tags the
// previous round read (the population a dual-target reader meets again), in [0, 15].
int gen2_start_q(const Gen2ReaderSpec& spec, bool first_round, uint64_t reads_last_round);

}  // namespace rfidray
