#include "core/gen2_inventory.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rfidray {
namespace {
constexpr uint64_t kWaiting = std::numeric_limits<uint64_t>::max();

// Uniform in [0, 2^q): the top q bits of one 64-bit draw (exact for a uniform generator).
uint64_t draw_slot(int q, Rng& rng) { return q == 0 ? 0 : (rng() >> (64 - q)); }
}  // namespace

void Gen2SlotStats::add(const Gen2SlotStats& o) {
  rounds += o.rounds;
  empty += o.empty;
  single += o.single;
  collided += o.collided;
  captured += o.captured;
  reads += o.reads;
  air_time_s += o.air_time_s;
}

void Gen2Round::draw(int q, Rng& rng) {
  for (uint64_t& s : slot_) s = current_ + draw_slot(q, rng);
}

void Gen2Round::begin(std::span<const uint32_t> participants, int q, Rng& rng) {
  ids_.assign(participants.begin(), participants.end());
  slot_.resize(ids_.size());
  current_ = 0;
  draw(q, rng);
}

void Gen2Round::query_adjust(int q, Rng& rng) {
  ++current_;
  draw(q, rng);
}

std::span<const uint32_t> Gen2Round::replies(const std::function<bool(uint32_t)>& powered) {
  replies_.clear();
  reply_pos_.clear();
  for (size_t k = 0; k < ids_.size();) {
    if (slot_[k] == current_) {
      if (powered && !powered(ids_[k])) {  // lost power: out of the round, no reply
        ids_.erase(ids_.begin() + static_cast<std::ptrdiff_t>(k));
        slot_.erase(slot_.begin() + static_cast<std::ptrdiff_t>(k));
        continue;
      }
      replies_.push_back(ids_[k]);
      reply_pos_.push_back(k);
    }
    ++k;
  }
  return replies_;
}

void Gen2Round::close_slot(std::optional<uint32_t> acknowledged) {
  // Positions in descending order so that removing one does not move the others still to visit.
  for (size_t r = reply_pos_.size(); r-- > 0;) {
    const size_t k = reply_pos_[r];
    if (acknowledged && ids_[k] == *acknowledged) {
      ids_.erase(ids_.begin() + static_cast<std::ptrdiff_t>(k));  // keeps participant order (determinism)
      slot_.erase(slot_.begin() + static_cast<std::ptrdiff_t>(k));
    } else {
      slot_[k] = kWaiting;
    }
  }
  replies_.clear();
  reply_pos_.clear();
}

double run_gen2_round(const Gen2ReaderSpec& spec, const Gen2LinkTiming& timing, std::span<const uint32_t> participants,
                      double t_s, double stop_s, Rng& rng, Gen2Round& round, Gen2SlotStats& stats,
                      const Gen2RoundHooks& hooks, int start_q) {
  const bool adaptive = spec.q_mode == Gen2QMode::kAdaptive;
  int q = adaptive ? std::clamp(start_q, 0, 15) : spec.q;
  double qfp = q;
  round.begin(participants, q, rng);
  ++stats.rounds;
  double command_s = timing.query_s;
  uint64_t frame_slot = 0;
  double t = t_s;
  while (t < stop_s) {
    const double reply_t = t + command_s + timing.t1_s;
    const std::span<const uint32_t> replies =
        hooks.powered ? round.replies([&](uint32_t tag) { return hooks.powered(tag, reply_t); }) : round.replies();
    std::optional<uint32_t> acknowledged;
    double slot_s = 0.0;
    if (replies.empty()) {
      ++stats.empty;
      slot_s = timing.empty_slot_s(command_s);
    } else {
      if (replies.size() == 1) {
        ++stats.single;
        acknowledged = replies[0];
      } else {
        ++stats.collided;
        if (spec.capture_ratio_db && hooks.reply_power_w) {
          // The strongest reply is decoded when it exceeds the sum of the others by the capture ratio.
          double best = -1.0, rest = 0.0;
          uint32_t best_tag = replies[0];
          for (uint32_t tag : replies) {
            const double p = hooks.reply_power_w(tag);
            if (p > best) {
              rest += std::max(best, 0.0);
              best = p;
              best_tag = tag;
            } else {
              rest += p;
            }
          }
          if (best > 0.0 && 10.0 * std::log10(best / std::max(rest, 1e-300)) >= *spec.capture_ratio_db) {
            ++stats.captured;
            acknowledged = best_tag;
          }
        }
      }
      if (acknowledged) {
        // The ACK and EPC follow; a reply that is not decoded leaves the tag unacknowledged (no flag flip).
        slot_s = timing.single_slot_s(command_s);
        if (hooks.read && hooks.read(*acknowledged, t + timing.epc_end_in_slot_s(command_s)))
          ++stats.reads;
        else
          acknowledged.reset();
      } else {
        slot_s = timing.collided_slot_s(command_s);
      }
      // A captured slot that was decoded took a single slot's time; one that was not, a collided slot's.
      if (!acknowledged && replies.size() == 1) slot_s = timing.single_slot_s(command_s);
    }
    const bool was_empty = replies.empty();
    const bool was_collided = replies.size() > 1;
    round.close_slot(acknowledged);
    t += slot_s;
    stats.air_time_s += slot_s;
    if (!adaptive) {
      if (++frame_slot >= (uint64_t{1} << q)) break;
      round.query_rep();
      command_s = timing.query_rep_s;
      continue;
    }
    if (was_empty && q == 0) break;
    if (was_empty) qfp = std::max(0.0, qfp - spec.q_c);
    if (was_collided) qfp = std::min(15.0, qfp + spec.q_c);
    const int next_q = static_cast<int>(std::lround(qfp));
    if (next_q != q) {
      q = next_q;
      round.query_adjust(q, rng);
      command_s = timing.query_adjust_s;
    } else {
      round.query_rep();
      command_s = timing.query_rep_s;
    }
  }
  return t;
}

}  // namespace rfidray

namespace rfidray {
int gen2_start_q(const Gen2ReaderSpec& spec, bool first_round, uint64_t reads_last_round) {
  if (first_round || spec.q_mode == Gen2QMode::kFixed) return spec.q;
  if (reads_last_round <= 1) return 0;
  return std::clamp(static_cast<int>(std::lround(std::log2(static_cast<double>(reads_last_round)))), 0, 15);
}
}  // namespace rfidray
