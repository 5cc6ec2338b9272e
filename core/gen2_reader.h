#pragma once
// A Gen2 reader's inventory settings (EPC UHF Gen2 Air Interface Protocol v1.2.0 / ISO/IEC 18000-63), as the
// scenario's `gen2:` block gives them: the link profile (core/gen2_link_timing.h), the session and target, Q
// (fixed, or the Q algorithm of Annex D), antenna ports with dwell times, a Select, and the capture rule.
// Plain values; validate() throws InputError naming the field. Presets: named reader modes defined by their values.
#include <optional>
#include <string>
#include <vector>

#include "core/gen2_link_timing.h"

namespace rfidray {

// Which inventoried flag a round's Query asks for (§6.3.2.11.2.1, Target). kAB: A, then B, alternating by round
// (a "dual target" search: every tag answers every round, its flag flipping each time).
enum class Gen2Target { kA, kB, kAB };
enum class Gen2QMode { kFixed, kAdaptive };

const char* to_string(Gen2Target t);
const char* to_string(Gen2QMode m);

// One antenna port: an antenna of the scenario (index into Scenario::antennas) and how long the reader stays on it.
struct Gen2Port {
  size_t antenna = 0;
  std::string antenna_name;  // as written (messages; resolved to `antenna` by the parser)
  double dwell_s = 0.0;      // > 0; a single port may have 0: always on
  int source_line = 0;
};

struct Gen2ReaderSpec {
  std::string preset;  // "" or the preset `link` came from (messages only)
  Gen2LinkParams link;
  int session = 0;                  // S0..S3 (§6.3.2.2)
  Gen2Target target = Gen2Target::kAB;
  int q = 4;                        // fixed Q, or the Q algorithm's starting Q_fp (0..15, §6.3.2.11.2.1)
  Gen2QMode q_mode = Gen2QMode::kAdaptive;
  double q_c = 0.3;                 // Annex D: Q_fp ± C per collided / empty slot, typically 0.1 < C < 0.5
  std::vector<Gen2Port> ports;      // empty: the reader's own antenna, always on
  // Select (§6.3.2.11.1.1): only tags whose name starts with this take part (each round begins with a Select
  // whose mask is the prefix, 8 bits a character). "": no Select.
  std::string select_prefix;
  // Capture: in a slot with several replies the strongest is decoded when its backscattered power exceeds the
  // sum of the others' by this ratio (dB). Unset: a slot with more than one reply is lost.
  std::optional<double> capture_ratio_db;
  // Inventoried-flag persistence (§6.3.2.2, "Tag flags and persistence values"): S1 0.5 s < t < 5 s whether
  // powered or not; S2, S3 indefinite while powered, t > 2 s unpowered; S0 indefinite powered, none unpowered.
  double s1_persistence_s = 2.0;
  double s23_persistence_s = 5.0;
  int source_line = 0;
};

// The reader modes a public reader document names (docs/air-protocol.md says where each value is from).
// "max_throughput": FM0, Tari 6.25 µs, BLF 640 kHz; "dense_reader_m4": Miller 4, Tari 25 µs, BLF 250 kHz.
// data-1 = 2 Tari for both (the documents give Tari and BLF only). Unknown name: nullopt.
std::optional<Gen2LinkParams> gen2_preset(const std::string& name);
std::vector<std::string> gen2_preset_names();

// Ranges of every value (the link through gen2_link_timing). `n_antennas` bounds the port indices.
void validate(const Gen2ReaderSpec& spec, size_t n_antennas, const std::string& field);

}  // namespace rfidray
