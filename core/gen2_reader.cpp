#include "core/gen2_reader.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/number_text.h"

namespace rfidray {

const char* to_string(Gen2Target t) {
  switch (t) {
    case Gen2Target::kA: return "A";
    case Gen2Target::kB: return "B";
    case Gen2Target::kAB: return "AB";
  }
  return "AB";
}
const char* to_string(Gen2QMode m) { return m == Gen2QMode::kFixed ? "fixed" : "adaptive"; }

std::optional<Gen2LinkParams> gen2_preset(const std::string& name) {
  Gen2LinkParams p;
  p.data1_tari = 2.0;
  if (name == "max_throughput") {
    p.tari_s = 6.25e-6;
    p.blf_hz = 640e3;
    p.encoding = Gen2Encoding::kFm0;
    return p;
  }
  if (name == "dense_reader_m4") {
    p.tari_s = 25e-6;
    p.blf_hz = 250e3;
    p.encoding = Gen2Encoding::kMiller4;
    return p;
  }
  return std::nullopt;
}

std::vector<std::string> gen2_preset_names() { return {"max_throughput", "dense_reader_m4"}; }

void validate(const Gen2ReaderSpec& s, size_t n_antennas, const std::string& field) {
  (void)gen2_link_timing(s.link, field);
  if (s.session < 0 || s.session > 3)
    throw field_error(field + ".session", "must be 0, 1, 2 or 3 (got " + std::to_string(s.session) + ")");
  if (s.q < 0 || s.q > 15) throw field_error(field + ".q", "must be in [0, 15] (Gen2 §6.3.2.11.2.1; got " + std::to_string(s.q) + ")");
  if (!(s.q_c > 0.0 && s.q_c < 1.0))
    throw field_error(field + ".q_c", "must be in (0, 1) (Gen2 Annex D: typically 0.1 < C < 0.5; got " + num(s.q_c) + ")");
  for (size_t i = 0; i < s.ports.size(); ++i) {
    const std::string f = field + ".ports[" + std::to_string(i) + "]";
    if (s.ports[i].antenna >= n_antennas) throw field_error(f + ".antenna", "no such antenna");
    const double d = s.ports[i].dwell_s;
    if (!(std::isfinite(d) && d >= 0.0 && d <= 1e6))
      throw field_error(f + ".dwell_ms", "must be in [0, 1e9] ms (got " + num(d * 1e3) + ")");
    if (d == 0.0 && s.ports.size() > 1)
      throw field_error(f + ".dwell_ms", "must be > 0 when the reader has several ports");
    if (d > 0.0 && d < 1e-3) throw field_error(f + ".dwell_ms", "must be >= 1 ms (got " + num(d * 1e3) + ")");
  }
  if (s.capture_ratio_db && !(std::isfinite(*s.capture_ratio_db) && *s.capture_ratio_db >= 0.0 && *s.capture_ratio_db <= 60.0))
    throw field_error(field + ".capture_db", "must be in [0, 60] dB (got " + num(*s.capture_ratio_db) + ")");
  if (s.select_prefix.size() > 32) throw field_error(field + ".select_prefix", "at most 32 characters (a 256-bit mask)");
  if (!(s.s1_persistence_s > 0.5 && s.s1_persistence_s < 5.0))
    throw field_error(field + ".s1_persistence_s", "must be in (0.5, 5) s (Gen2 §6.3.2.2; got " + num(s.s1_persistence_s) + ")");
  if (!(s.s23_persistence_s > 2.0 && s.s23_persistence_s <= 1e6))
    throw field_error(field + ".s23_persistence_s", "must be > 2 s (Gen2 §6.3.2.2; got " + num(s.s23_persistence_s) + ")");
}

}  // namespace rfidray
