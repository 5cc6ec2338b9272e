#include "core/gen2_link_timing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/number_text.h"

namespace rfidray {
namespace {

double mean_bit_s(double rtcal_s) { return 0.5 * rtcal_s; }  // (data-0 + data-1)/2 = RTcal/2

}  // namespace

const char* to_string(Gen2Encoding e) {
  switch (e) {
    case Gen2Encoding::kFm0: return "fm0";
    case Gen2Encoding::kMiller2: return "miller2";
    case Gen2Encoding::kMiller4: return "miller4";
    case Gen2Encoding::kMiller8: return "miller8";
  }
  return "fm0";
}

Gen2Encoding parse_gen2_encoding(const std::string& name, const std::string& field) {
  for (Gen2Encoding e : {Gen2Encoding::kFm0, Gen2Encoding::kMiller2, Gen2Encoding::kMiller4, Gen2Encoding::kMiller8})
    if (name == to_string(e)) return e;
  throw field_error(field, "unknown encoding '" + clip(name) + "' (fm0, miller2, miller4, miller8)");
}

double gen2_reply_s(const Gen2LinkParams& p, int bits) {
  const int m = static_cast<int>(p.encoding);
  // §6.3.1.3.2: FM0 preamble 6 symbols (+12 pilot zeros with TRext); Miller 4 (TRext: 16) pilot symbols + 6.
  const int preamble_symbols = m == 1 ? (p.trext ? 18 : 6) : (p.trext ? 22 : 10);
  const int symbols = preamble_symbols + bits + 1;  // + the dummy data-1 that ends every reply
  return symbols * m / p.blf_hz;
}

double Gen2LinkTiming::select_s(int mask_bits) const {
  return frame_sync_s + (gen2::kSelectBaseBits + mask_bits) * mean_bit_s(rtcal_s);
}
double Gen2LinkTiming::empty_slot_s(double command_s) const { return command_s + std::max(t1_s + t3_s, t4_s); }
double Gen2LinkTiming::collided_slot_s(double command_s) const { return command_s + t1_s + rn16_reply_s + t2_s; }
double Gen2LinkTiming::epc_end_in_slot_s(double command_s) const {
  return command_s + t1_s + rn16_reply_s + t2_s + ack_s + t1_s + epc_reply_s;
}
double Gen2LinkTiming::single_slot_s(double command_s) const { return epc_end_in_slot_s(command_s) + t2_s; }

Gen2LinkTiming gen2_link_timing(const Gen2LinkParams& p, const std::string& field) {
  auto err = [&](const char* key, const std::string& what) { return field_error(field + "." + key, what); };
  const double tari_us = p.tari_s * 1e6;
  if (!(p.tari_s >= gen2::kMinTari_s * (1 - 1e-9) && p.tari_s <= gen2::kMaxTari_s * (1 + 1e-9)))
    throw err("tari_us", "must be in [6.25, 25] µs (Gen2 §6.3.1.2.4; got " + num(tari_us) + ")");
  if (!(p.data1_tari >= gen2::kMinData1Tari && p.data1_tari <= gen2::kMaxData1Tari))
    throw err("data1_tari", "must be in [1.5, 2.0] Tari (Gen2 §6.3.1.2.3; got " + num(p.data1_tari) + ")");
  if (!(p.blf_hz >= gen2::kMinBlfHz * (1 - 1e-9) && p.blf_hz <= gen2::kMaxBlfHz * (1 + 1e-9)))
    throw err("blf_khz", "must be in [40, 640] kHz (Gen2 §6.3.1.3.3; got " + num(p.blf_hz / 1e3) + ")");
  if (!(p.epc_bits >= 16 && p.epc_bits <= 496 && p.epc_bits % 16 == 0))
    throw err("epc_bits", "must be a multiple of 16 in [16, 496] (Gen2 §6.3.2.1.2; got " + std::to_string(p.epc_bits) + ")");
  if (!(p.t2_tpri >= gen2::kMinT2Tpri && p.t2_tpri <= gen2::kMaxT2Tpri))
    throw err("t2_tpri", "must be in [3, 20] Tpri (Gen2 §6.3.1.6; got " + num(p.t2_tpri) + ")");
  if (!(p.t3_s >= 0.0 && p.t3_s <= 1.0))
    throw err("t3_us", "must be in [0, 1e6] µs (got " + num(p.t3_s * 1e6) + ")");

  Gen2LinkTiming t;
  t.rtcal_s = (1.0 + p.data1_tari) * p.tari_s;
  // BLF = DR/TRcal (§6.3.1.3.3): prefer DR = 64/3, else 8, whichever puts TRcal in [1.1, 3]·RTcal (§6.3.1.2.8).
  bool found = false;
  for (double dr : {64.0 / 3.0, 8.0}) {
    const double trcal = dr / p.blf_hz;
    if (trcal >= gen2::kMinTrcalRtcal * t.rtcal_s * (1 - 1e-9) && trcal <= gen2::kMaxTrcalRtcal * t.rtcal_s * (1 + 1e-9)) {
      t.divide_ratio = dr;
      t.trcal_s = trcal;
      found = true;
      break;
    }
  }
  if (!found)
    throw err("blf_khz", "BLF " + num(p.blf_hz / 1e3) + " kHz needs TRcal = DR/BLF (DR 64/3 or 8) within [1.1, 3]·RTcal = [" +
                             num(1.1 * t.rtcal_s * 1e6) + ", " + num(3.0 * t.rtcal_s * 1e6) + "] µs for Tari " +
                             num(tari_us) + " µs (Gen2 §6.3.1.2.8, §6.3.1.3.3): no divide ratio fits");
  t.tpri_s = 1.0 / p.blf_hz;
  t.t1_s = std::max(t.rtcal_s, 10.0 * t.tpri_s);
  t.t2_s = p.t2_tpri * t.tpri_s;
  t.t3_s = p.t3_s;
  t.t4_s = 2.0 * t.rtcal_s;
  t.frame_sync_s = gen2::kDelimiter_s + p.tari_s + t.rtcal_s;
  t.preamble_s = t.frame_sync_s + t.trcal_s;
  const double bit = mean_bit_s(t.rtcal_s);
  t.query_s = t.preamble_s + gen2::kQueryBits * bit;
  t.query_rep_s = t.frame_sync_s + gen2::kQueryRepBits * bit;
  t.query_adjust_s = t.frame_sync_s + gen2::kQueryAdjustBits * bit;
  t.ack_s = t.frame_sync_s + gen2::kAckBits * bit;
  t.rn16_reply_s = gen2_reply_s(p, gen2::kRn16Bits);
  t.epc_reply_s = gen2_reply_s(p, gen2::kPcBits + p.epc_bits + gen2::kCrc16Bits);
  return t;
}

}  // namespace rfidray
