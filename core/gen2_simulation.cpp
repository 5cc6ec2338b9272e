#include "core/gen2_simulation.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>

#include "core/error.h"
#include "core/gen2_inventory.h"
#include "core/reader_model.h"
#include "core/tag_couplings.h"
#include "core/units.h"

namespace rfidray {
namespace {

constexpr uint64_t kGen2Stream = 0x67656e32ULL;  // "gen2"
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string where(const Scenario& s, int line) {
  if (s.source.empty()) return "";
  return line > 0 ? s.source + ":" + std::to_string(line) + ": " : s.source + ": ";
}

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::vector<Gen2Port> ports_of(const Scenario& s, size_t a) {
  const Gen2ReaderSpec& g = *s.antennas[a].gen2;
  if (!g.ports.empty()) return g.ports;
  Gen2Port p;
  p.antenna = a;
  p.antenna_name = s.antennas[a].reader.name;
  return {p};
}

// The end of the hop dwell that contains t (infinity without hopping), strictly after t.
double next_hop_s(const ReaderParams& r, double t) {
  if (r.frequencies_hz.size() <= 1 || !(r.hop_dwell_s > 0.0)) return kInf;
  double next = (std::floor(t / r.hop_dwell_s) + 1.0) * r.hop_dwell_s;
  if (next <= t) next += r.hop_dwell_s;
  return next;
}

struct CachedH {
  bool valid = false;
  Pose antenna_pose, tag_pose;
  std::complex<double> h{0.0, 0.0};
};

// One reader's run: its own state, written only by the thread that runs it.
class ReaderRun {
 public:
  ReaderRun(const Scenario& s, const SceneMotion& m, const Channel& ch, const TagCouplings& cp, size_t reader,
            double duration_s)
      : s_(s), m_(m), ch_(ch), cp_(cp), reader_(reader), duration_s_(duration_s), spec_(*s.antennas[reader].gen2),
        ports_(ports_of(s, reader)), n_tags_(s.tags.size()) {
    timing_ = gen2_link_timing(spec_.link, "antennas[" + std::to_string(reader) + "].gen2");
    results_.resize(ports_.size());
    for (auto& r : results_) r.gen2 = Gen2SlotStats{};
    flag_b_.assign(n_tags_, 0);
    flip_s_.assign(n_tags_, 0.0);
    unpowered_since_s_.assign(n_tags_, -1.0);
    selected_.assign(n_tags_, 1);
    if (!spec_.select_prefix.empty())
      for (size_t i = 0; i < n_tags_; ++i)
        selected_[i] = s.tags[i].tag.name.rfind(spec_.select_prefix, 0) == 0 ? 1 : 0;
    power_w_.assign(n_tags_, 0.0);
    dist_.assign(n_tags_, 0.0);
    tag_pose_.assign(n_tags_, Pose{});
    h_.assign(n_tags_, {0.0, 0.0});
    read_counter_.assign(ports_.size(), 0);
    if (ch_.cacheable()) {
      const size_t n_ch = s.antennas[reader].reader.frequencies_hz.size();
      cache_.resize(ports_.size() * n_ch * n_tags_);
    }
  }

  void run() {
    const ReaderParams& owner = s_.antennas[reader_].reader;
    double t = std::max(0.0, s_.antennas[reader_].start_s);
    size_t port = 0;
    double port_end = ports_[0].dwell_s > 0.0 ? t + ports_[0].dwell_s : kInf;
    uint64_t period = 0, round_index = 0;
    const double select_s = spec_.select_prefix.empty() ? 0.0 : timing_.select_s(8 * int(spec_.select_prefix.size()));
    while (t < duration_s_) {
      const size_t c = hop_index_at(owner, t);
      const double period_end = std::min({port_end, next_hop_s(owner, t), duration_s_});
      Rng rng = make_stream(s_.seed, {kGen2Stream, static_cast<uint64_t>(reader_), period++});
      // The carrier was off (start, port switch, hop): S0 flags do not survive it (§6.3.2.2).
      if (spec_.session == 0) std::fill(flag_b_.begin(), flag_b_.end(), 0);
      Gen2SlotStats& stats = *results_[port].gen2;
      while (t < period_end) {
        if (select_s > 0.0) {
          t += select_s;
          stats.air_time_s += select_s;
          if (!(t < period_end)) break;
        }
        const bool target_b = spec_.target == Gen2Target::kB || (spec_.target == Gen2Target::kAB && round_index % 2 == 1);
        ++round_index;
        participants_.clear();
        evaluate_tags(port, c, t, target_b);
        Gen2RoundHooks hooks;
        hooks.read = [&](uint32_t tag, double epc_end_s) { return read(port, c, tag, epc_end_s, target_b); };
        hooks.powered = [&](uint32_t tag, double reply_s) { return still_powered(port, tag, reply_s); };
        if (spec_.capture_ratio_db) hooks.reply_power_w = [&](uint32_t tag) { return power_w_[tag]; };
        const uint64_t slots_before = stats.slots(), reads_before = stats.reads;
        t = run_gen2_round(spec_, timing_, participants_, t, period_end, rng, round_, stats, hooks,
                           gen2_start_q(spec_, round_index == 1, last_round_reads_));
        results_[port].ticks += stats.slots() - slots_before;
        last_round_reads_ = stats.reads - reads_before;
      }
      t = std::max(t, period_end);
      if (t >= port_end) {
        port = (port + 1) % ports_.size();
        port_end = ports_[port].dwell_s > 0.0 ? t + ports_[port].dwell_s : kInf;
      }
    }
  }

  std::vector<AntennaResult>& results() { return results_; }
  const std::vector<Gen2Port>& ports() const { return ports_; }

 private:
  InputError coincident(size_t a, size_t i, double t, double d) const {
    return InputError(where(s_, s_.tags[i].source_line) + "tag '" + s_.tags[i].tag.name + "' is at antenna '" +
                      s_.antennas[a].reader.name + "' at t = " + fmt(t) + " s (distance " + fmt(d) +
                      " m; the models need D > 0)");
  }

  // h for tags `idx` (poses in tag_pose_) from the port's antenna at `centre`, reusing unchanged links.
  void channel_for(size_t port, size_t c, const Pose& centre, std::span<const size_t> idx) {
    const size_t a = ports_[port].antenna;
    const ReaderParams& r = s_.antennas[a].reader;
    missing_.clear();
    batch_.clear();
    for (size_t i : idx) {
      if (!cache_.empty()) {
        const CachedH& e = cache_[(port * r.frequencies_hz.size() + c) * n_tags_ + i];
        if (e.valid && e.antenna_pose == centre && e.tag_pose == tag_pose_[i]) {
          h_[i] = e.h;
          continue;
        }
      }
      missing_.push_back(i);
      batch_.push_back({tag_pose_[i], s_.tags[i].tag.pattern, s_.tags[i].tag.polarization});
    }
    if (batch_.empty()) return;
    batch_h_.resize(batch_.size());
    ch_.one_way({centre, r.pattern, r.polarization}, batch_, r.frequencies_hz[c], batch_h_);
    for (size_t k = 0; k < missing_.size(); ++k) {
      const size_t i = missing_[k];
      h_[i] = batch_h_[k];
      if (!cache_.empty()) cache_[(port * r.frequencies_hz.size() + c) * n_tags_ + i] = {true, centre, tag_pose_[i], h_[i]};
    }
  }

  // Who takes part in the round starting at t: present, selected, powered, flag = target; updates persistence.
  void evaluate_tags(size_t port, size_t c, double t, bool target_b) {
    const size_t a = ports_[port].antenna;
    const ReaderParams& r = s_.antennas[a].reader;
    const Pose ap = m_.antennas[a]->pose_at(t);
    const Pose centre = phase_centre_pose(r, ap);
    present_.clear();
    for (size_t i = 0; i < n_tags_; ++i) {
      if (!selected_[i] || t < s_.tags[i].start_s) continue;
      tag_pose_[i] = m_.tags[i]->pose_at(t);
      dist_[i] = (tag_pose_[i].position - centre.position).norm();
      if (!(dist_[i] >= kMinLinkDistance_m)) throw coincident(a, i, t, dist_[i]);
      present_.push_back(i);
    }
    const bool physical = r.model == ReaderModelKind::kPhysical;
    if (physical) channel_for(port, c, centre, present_);
    const double p_tx_w = dbm_to_watt(r.tx_power_dbm);
    const double lambda = wavelength_m(r.frequencies_hz[c]);
    for (size_t i : present_) {
      bool powered = false;
      if (physical) {
        const TagCoupling* cp = cp_.at(i, a, c);
        std::complex<double> h = h_[i];
        if (cp) h *= backing_image_factor(cp_.backings()[i], tag_pose_[i], centre.position, r.frequencies_hz[c]);
        const double g2 = std::norm(h);
        powered = p_tx_w * (cp ? cp->chip_power_factor : 1.0) * g2 >= dbm_to_watt(s_.tags[i].tag.chip_sensitivity_dbm);
        power_w_[i] = p_tx_w * (cp ? cp->modulation_factor : r.modulation_factor) * g2 * g2;
      } else {
        powered = dist_[i] <= r.range_m;
        const double amp = r.communication_gain * lambda / (4.0 * kPi * dist_[i]);
        power_w_[i] = amp * amp * amp * amp;  // eq. 5's amplitude to the 4th: relative backscatter power
      }
      if (!powered) {
        if (unpowered_since_s_[i] < 0.0) unpowered_since_s_[i] = t;
        if (spec_.session == 0) flag_b_[i] = 0;
        continue;
      }
      if (unpowered_since_s_[i] >= 0.0) {
        if (spec_.session >= 2 && t - unpowered_since_s_[i] > spec_.s23_persistence_s) flag_b_[i] = 0;
        unpowered_since_s_[i] = -1.0;
      }
      if (spec_.session == 1 && flag_b_[i] && t - flip_s_[i] >= spec_.s1_persistence_s) flag_b_[i] = 0;
      if (static_cast<bool>(flag_b_[i]) == target_b) participants_.push_back(static_cast<uint32_t>(i));
    }
  }

  // Whether a tag of the round is still powered at its reply time t (it may have left the field since the Query).
  bool still_powered(size_t port, uint32_t tag, double t) {
    if (t > duration_s_) return true;  // the run ends first; its read is not recorded anyway
    const size_t a = ports_[port].antenna;
    const ReaderParams& r = s_.antennas[a].reader;
    if (m_.antennas[a]->is_static() && m_.tags[tag]->is_static()) return true;  // as at the Query
    const Pose centre = phase_centre_pose(r, m_.antennas[a]->pose_at(t));
    tag_pose_[tag] = m_.tags[tag]->pose_at(t);
    dist_[tag] = (tag_pose_[tag].position - centre.position).norm();
    if (!(dist_[tag] >= kMinLinkDistance_m)) throw coincident(a, tag, t, dist_[tag]);
    bool powered = true;
    if (r.model == ReaderModelKind::kPhysical) {
      const size_t c = hop_index_at(r, t);
      const size_t one[1] = {tag};
      channel_for(port, c, centre, one);
      const TagCoupling* cp = cp_.at(tag, a, c);
      std::complex<double> h = h_[tag];
      if (cp) h *= backing_image_factor(cp_.backings()[tag], tag_pose_[tag], centre.position, r.frequencies_hz[c]);
      powered = dbm_to_watt(r.tx_power_dbm) * (cp ? cp->chip_power_factor : 1.0) * std::norm(h) >=
                dbm_to_watt(s_.tags[tag].tag.chip_sensitivity_dbm);
    } else {
      powered = dist_[tag] <= r.range_m;
    }
    if (!powered) {
      if (unpowered_since_s_[tag] < 0.0) unpowered_since_s_[tag] = t;
      if (spec_.session == 0) flag_b_[tag] = 0;
    }
    return powered;
  }

  // The acknowledged tag's EPC reply ends at t: read_tag() there decides; a read flips the tag's flag.
  bool read(size_t port, size_t c, uint32_t tag, double t, bool target_b) {
    if (t > duration_s_) return false;
    const size_t a = ports_[port].antenna;
    const ReaderParams& r = s_.antennas[a].reader;
    const Pose ap = m_.antennas[a]->pose_at(t);
    const Pose centre = phase_centre_pose(r, ap);
    tag_pose_[tag] = m_.tags[tag]->pose_at(t);
    dist_[tag] = (tag_pose_[tag].position - centre.position).norm();
    if (!(dist_[tag] >= kMinLinkDistance_m)) throw coincident(a, tag, t, dist_[tag]);
    const size_t one[1] = {tag};
    // The carrier of the reply's end (a hop may have come since the Query): read_attempts takes it from the
    // port's hopping, which is the reader's (checked in gen2_driven_antennas).
    c = hop_index_at(r, t);
    if (r.model == ReaderModelKind::kPhysical) channel_for(port, c, centre, one);
    const size_t before = results_[port].reads.size();
    const uint64_t k = read_counter_[port]++;
    ++results_[port].attempts;
    read_attempts(s_, a, k, t, ap, one, dist_, tag_pose_, h_, results_[port].reads, &cp_);
    if (results_[port].reads.size() == before) return false;
    flag_b_[tag] = target_b ? 0 : 1;
    flip_s_[tag] = t;
    return true;
  }

  const Scenario& s_;
  const SceneMotion& m_;
  const Channel& ch_;
  const TagCouplings& cp_;
  size_t reader_;
  double duration_s_;
  const Gen2ReaderSpec& spec_;
  std::vector<Gen2Port> ports_;
  size_t n_tags_;
  Gen2LinkTiming timing_;
  std::vector<AntennaResult> results_;  // per port
  std::vector<char> flag_b_, selected_;
  std::vector<double> flip_s_, unpowered_since_s_, power_w_, dist_;
  std::vector<Pose> tag_pose_;
  std::vector<std::complex<double>> h_;
  std::vector<uint64_t> read_counter_;
  std::vector<CachedH> cache_;
  std::vector<size_t> present_, missing_;
  std::vector<uint32_t> participants_;
  std::vector<Endpoint> batch_;
  std::vector<std::complex<double>> batch_h_;
  Gen2Round round_;
  uint64_t last_round_reads_ = 0;
};

}  // namespace

std::vector<bool> gen2_driven_antennas(const Scenario& s) {
  const size_t n = s.antennas.size();
  std::vector<bool> driven(n, false);
  std::vector<long> owner(n, -1);
  for (size_t a = 0; a < n; ++a) {
    if (!s.antennas[a].gen2) continue;
    const std::string field = "antennas[" + std::to_string(a) + "].gen2";
    const int line = s.antennas[a].gen2->source_line ? s.antennas[a].gen2->source_line : s.antennas[a].source_line;
    try {
      validate(*s.antennas[a].gen2, n, field);
    } catch (const InputError& e) {
      throw InputError(where(s, line) + e.what());
    }
    for (const Gen2Port& p : ports_of(s, a)) {
      const AntennaSpec& port = s.antennas[p.antenna];
      if (owner[p.antenna] >= 0 && owner[p.antenna] != static_cast<long>(a))
        throw InputError(where(s, line) + "field '" + field + ".ports': antenna '" + port.reader.name +
                         "' is already a port of reader '" + s.antennas[static_cast<size_t>(owner[p.antenna])].reader.name + "'");
      if (p.antenna != a && port.gen2)
        throw InputError(where(s, line) + "field '" + field + ".ports': antenna '" + port.reader.name +
                         "' is a Gen2 reader itself (a port has no gen2 block)");
      if (port.reader.frequencies_hz != s.antennas[a].reader.frequencies_hz ||
          (port.reader.frequencies_hz.size() > 1 && port.reader.hop_dwell_s != s.antennas[a].reader.hop_dwell_s))
        throw InputError(where(s, line) + "field '" + field + ".ports': antenna '" + port.reader.name +
                         "' has other carriers or hop dwell than its reader '" + s.antennas[a].reader.name +
                         "' (one synthesizer feeds every port: give the port the same frequency/hopping keys)");
      owner[p.antenna] = static_cast<long>(a);
      driven[p.antenna] = true;
    }
  }
  for (size_t a = 0; a < n; ++a)
    if (s.antennas[a].gen2 && owner[a] >= 0 && owner[a] != static_cast<long>(a))
      throw InputError(where(s, s.antennas[a].source_line) + "field 'antennas[" + std::to_string(a) +
                       "].gen2': antenna '" + s.antennas[a].reader.name + "' is a port of reader '" +
                       s.antennas[static_cast<size_t>(owner[a])].reader.name + "' and cannot be a reader itself");
  return driven;
}

void simulate_gen2(const Scenario& scenario, const SceneMotion& motion, const Channel& channel,
                   const TagCouplings& couplings, double duration_s, int threads, SimulationResult& result) {
  (void)gen2_driven_antennas(scenario);  // validates
  std::vector<size_t> readers;
  for (size_t a = 0; a < scenario.antennas.size(); ++a)
    if (scenario.antennas[a].gen2) readers.push_back(a);
  if (readers.empty()) return;
  std::vector<std::unique_ptr<ReaderRun>> runs(readers.size());
  std::vector<std::exception_ptr> errors(readers.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads))
  for (size_t k = 0; k < readers.size(); ++k) {
    try {
      runs[k] = std::make_unique<ReaderRun>(scenario, motion, channel, couplings, readers[k], duration_s);
      runs[k]->run();
    } catch (...) {  // exceptions must not leave an OpenMP region; rethrown below in reader order
      errors[k] = std::current_exception();
    }
  }
  for (size_t k = 0; k < readers.size(); ++k) {
    if (errors[k]) {
      try {
        std::rethrow_exception(errors[k]);
      } catch (const InputError& e) {
        const std::string msg = e.what();
        // Errors of the gen2 block come without the location; the tag errors have it.
        if (!scenario.source.empty() && msg.rfind(scenario.source, 0) != 0)
          throw InputError(where(scenario, scenario.antennas[readers[k]].source_line) + msg);
        throw;
      }
    }
    for (size_t p = 0; p < runs[k]->ports().size(); ++p)
      result.antennas[runs[k]->ports()[p].antenna] = std::move(runs[k]->results()[p]);
  }
}

}  // namespace rfidray
