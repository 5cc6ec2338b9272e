#pragma once
// EPC UHF Gen2 link timing: how long each reader command and tag reply of an inventory lasts on air, from a
// link profile (Tari, data-1, BLF, encoding, pilot tone). Every number is from the EPC UHF Gen2 Air Interface
// Protocol (GS1, version 1.2.0 section numbering; the same clauses are in ISO/IEC 18000-63):
//   §6.3.1.2.3  PIE: data-0 lasts Tari, data-1 between 1.5 and 2.0 Tari;
//   §6.3.1.2.4  Tari 6.25 µs to 25 µs;
//   §6.3.1.2.8  preamble = delimiter (12.5 µs) + data-0 + RTcal + TRcal, frame-sync = delimiter + data-0 + RTcal;
//               RTcal = data-0 + data-1 (2.5 to 3.0 Tari); 1.1·RTcal ≤ TRcal ≤ 3·RTcal; Query alone has the
//               preamble, every other command the frame-sync;
//   §6.3.1.3.2  FM0: one bit per 1/BLF, preamble 6 symbols (TRext = 1: 12 leading zeros more); Miller M: one
//               bit per M/BLF, preamble 4 (TRext = 1: 16) pilot symbols + the 6 symbols 010111; every reply
//               ends with a dummy data-1;
//   §6.3.1.3.3  BLF = DR/TRcal, DR = 8 or 64/3; BLF 40 kHz to 640 kHz;
//   §6.3.1.6    link timings: T1 = max(RTcal, 10·Tpri) (nominal), T2 from 3 to 20 Tpri, T3 ≥ 0, T4 = 2·RTcal
//               (minimum), Tpri = 1/BLF;
//   §6.3.2.11   Query 22 bits, QueryRep 4, QueryAdjust 9, ACK 18 (2 + RN16), NAK 8, Select 45 + mask bits
//               (8-bit EBV pointer); replies: RN16 = 16 bits, after ACK PC (16) + EPC + CRC-16 (16).
// A command's bits are PIE symbols whose length depends on their value; the air time of one bit is taken as
// the mean of data-0 and data-1, RTcal/2 (the content — RN16s, CRCs — is random, so that is its expectation).
// Value types, pure functions: thread-safe. validate() throws InputError naming the field.
#include <string>

namespace rfidray {

enum class Gen2Encoding { kFm0 = 1, kMiller2 = 2, kMiller4 = 4, kMiller8 = 8 };  // value: M (FM0: 1)

const char* to_string(Gen2Encoding e);
// "fm0", "miller2", "miller4", "miller8"; throws InputError naming `field` otherwise.
Gen2Encoding parse_gen2_encoding(const std::string& name, const std::string& field);

// Spec constants (see the header comment for the clauses).
namespace gen2 {
inline constexpr double kDelimiter_s = 12.5e-6;
inline constexpr double kMinTari_s = 6.25e-6, kMaxTari_s = 25e-6;
inline constexpr double kMinData1Tari = 1.5, kMaxData1Tari = 2.0;
inline constexpr double kMinBlfHz = 40e3, kMaxBlfHz = 640e3;
inline constexpr double kMinTrcalRtcal = 1.1, kMaxTrcalRtcal = 3.0;
inline constexpr int kQueryBits = 22, kQueryRepBits = 4, kQueryAdjustBits = 9, kAckBits = 18, kNakBits = 8;
inline constexpr int kSelectBaseBits = 45;
inline constexpr int kRn16Bits = 16, kPcBits = 16, kCrc16Bits = 16;
inline constexpr double kMinT2Tpri = 3.0, kMaxT2Tpri = 20.0;
}  // namespace gen2

// One link profile. Defaults: the dense-reader Miller-4 profile (Tari 25 µs, BLF 250 kHz).
struct Gen2LinkParams {
  double tari_s = 25e-6;
  double data1_tari = 2.0;  // data-1 in Tari; RTcal = (1 + data1_tari)·Tari
  double blf_hz = 250e3;
  Gen2Encoding encoding = Gen2Encoding::kMiller4;
  bool trext = false;       // pilot tone (Query's TRext bit)
  int epc_bits = 96;
  double t2_tpri = 3.0;     // the reader answers T2 after a reply ends; 3 Tpri: as soon as the spec allows
  double t3_s = 0.0;        // extra wait of the reader in an empty slot, beyond T1
};

// What the profile gives on air (seconds). Built by gen2_link_timing(), which validates.
struct Gen2LinkTiming {
  double rtcal_s = 0, trcal_s = 0, divide_ratio = 0, tpri_s = 0;
  double t1_s = 0, t2_s = 0, t3_s = 0, t4_s = 0;
  double preamble_s = 0, frame_sync_s = 0;
  double query_s = 0, query_rep_s = 0, query_adjust_s = 0, ack_s = 0;
  double rn16_reply_s = 0, epc_reply_s = 0;  // from the first preamble symbol to the end of the dummy 1
  double select_s(int mask_bits) const;      // frame-sync + (45 + mask) bits

  // Slot air time of each outcome, from the start of its command (Query/QueryRep/QueryAdjust of `command_s`)
  // to the start of the next command:
  //  empty:     command + max(T1 + T3, T4)                 (no reply; the next command may start T4 after)
  //  collided:  command + T1 + RN16 + T2                   (the garbled RN16 is heard out, then the next one)
  //  single:    command + T1 + RN16 + T2 + ACK + T1 + EPC + T2
  double empty_slot_s(double command_s) const;
  double collided_slot_s(double command_s) const;
  double single_slot_s(double command_s) const;
  // Time from the start of a single slot's command to the end of the EPC reply (the read's timestamp).
  double epc_end_in_slot_s(double command_s) const;
};

// Computes the timing; DR is 64/3 unless only 8 gives 1.1·RTcal ≤ TRcal ≤ 3·RTcal. Throws InputError naming
// `field` (e.g. "antennas[0].gen2") and the key when a value is outside the spec's range.
Gen2LinkTiming gen2_link_timing(const Gen2LinkParams& p, const std::string& field);

// Duration of a reply of `bits` data bits (FM0 or Miller, preamble and dummy 1 included).
double gen2_reply_s(const Gen2LinkParams& p, int bits);

}  // namespace rfidray
