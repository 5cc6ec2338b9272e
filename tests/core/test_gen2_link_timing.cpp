// Gen2 link timing against the spec's formulas, written out here from the spec's clauses (EPC UHF Gen2 v1.2.0
// §6.3.1.2.3, §6.3.1.2.8, §6.3.1.3.2, §6.3.1.3.3, §6.3.1.6, §6.3.2.11), not taken from the implementation.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"
#include "core/gen2_link_timing.h"
#include "core/gen2_reader.h"

namespace rfidray {
namespace {

// One Query→RN16→ACK→EPC cycle (96-bit EPC), in µs, straight from the formulas:
//   RTcal = Tari + data-1; bit = RTcal/2 (mean PIE symbol); preamble = 12.5 + Tari + RTcal + TRcal,
//   frame-sync = 12.5 + Tari + RTcal; TRcal = DR/BLF; Query 22 bits, ACK 18;
//   reply (FM0) = (6 [+12 TRext] + bits + 1)/BLF, (Miller M) = (10 [+12 TRext] + bits + 1)·M/BLF;
//   T1 = max(RTcal, 10/BLF), T2 = 3/BLF.
double cycle_us(double tari_us, double data1_tari, double blf_khz, int m, bool trext, double dr) {
  const double rtcal = tari_us * (1.0 + data1_tari);
  const double trcal = dr / blf_khz * 1e3;
  const double bit = rtcal / 2.0;
  const double query = 12.5 + tari_us + rtcal + trcal + 22 * bit;
  const double ack = 12.5 + tari_us + rtcal + 18 * bit;
  const double tpri = 1e3 / blf_khz;
  const double t1 = std::max(rtcal, 10 * tpri), t2 = 3 * tpri;
  const int preamble = m == 1 ? (trext ? 18 : 6) : (trext ? 22 : 10);
  const double rn16 = (preamble + 16 + 1) * m * tpri;
  const double epc = (preamble + 16 + 96 + 16 + 1) * m * tpri;
  return query + t1 + rn16 + t2 + ack + t1 + epc + t2;
}

double impl_cycle_us(const Gen2LinkParams& p) {
  const Gen2LinkTiming t = gen2_link_timing(p, "gen2");
  return t.single_slot_s(t.query_s) * 1e6;
}

TEST(Gen2LinkTiming, MaxThroughputCycleMatchesFormulas) {
  const Gen2LinkParams p = *gen2_preset("max_throughput");
  // Tari 6.25 µs, BLF 640 kHz, FM0: TRcal = (64/3)/640 kHz = 33.3 µs lies in [1.1, 3]·RTcal = [20.6, 56.3] µs.
  const double expected = cycle_us(6.25, 2.0, 640.0, 1, false, 64.0 / 3.0);
  EXPECT_NEAR(impl_cycle_us(p), expected, 1e-9 * expected);
  // Hand check of the sum: Query 277.0833 + T1 18.75 + RN16 35.9375 + T2 4.6875 + ACK 206.25 + T1 18.75
  // + EPC 210.9375 + T2 4.6875 µs.
  EXPECT_NEAR(expected, 777.083333, 1e-5);
}

TEST(Gen2LinkTiming, DenseReaderM4CycleMatchesFormulas) {
  const Gen2LinkParams p = *gen2_preset("dense_reader_m4");
  const double expected = cycle_us(25.0, 2.0, 250.0, 4, false, 64.0 / 3.0);
  EXPECT_NEAR(impl_cycle_us(p), expected, 1e-9 * expected);
  const Gen2LinkTiming t = gen2_link_timing(p, "gen2");
  EXPECT_NEAR(t.trcal_s * 1e6, 85.333333, 1e-5);  // 64/3 / 250 kHz
  EXPECT_NEAR(t.t1_s * 1e6, 75.0, 1e-9);           // RTcal > 10 Tpri = 40 µs
  EXPECT_NEAR(t.rn16_reply_s * 1e6, 27 * 16.0, 1e-9);
}

TEST(Gen2LinkTiming, Miller8PilotToneWithDivideRatio8) {
  Gen2LinkParams p;
  p.tari_s = 12.5e-6;
  p.data1_tari = 1.5;
  p.blf_hz = 160e3;
  p.encoding = Gen2Encoding::kMiller8;
  p.trext = true;
  // DR 64/3 would need TRcal = 133 µs > 3·RTcal = 93.75 µs: only DR = 8 (TRcal 50 µs) fits.
  const Gen2LinkTiming t = gen2_link_timing(p, "gen2");
  EXPECT_DOUBLE_EQ(t.divide_ratio, 8.0);
  const double expected = cycle_us(12.5, 1.5, 160.0, 8, true, 8.0);
  EXPECT_NEAR(impl_cycle_us(p), expected, 1e-9 * expected);
  EXPECT_NEAR(t.t1_s * 1e6, 62.5, 1e-9);  // 10 Tpri > RTcal = 31.25 µs
}

TEST(Gen2LinkTiming, Fm0PilotToneSlowLink) {
  Gen2LinkParams p;
  p.tari_s = 25e-6;
  p.blf_hz = 40e3;
  p.encoding = Gen2Encoding::kFm0;
  p.trext = true;
  const double expected = cycle_us(25.0, 2.0, 40.0, 1, true, 8.0);
  EXPECT_NEAR(impl_cycle_us(p), expected, 1e-9 * expected);
}

TEST(Gen2LinkTiming, EmptyAndCollidedSlots) {
  const Gen2LinkTiming t = gen2_link_timing(*gen2_preset("dense_reader_m4"), "gen2");
  // QueryRep = frame-sync (12.5 + 25 + 75) + 4 bits of 37.5 µs = 262.5 µs; empty: + max(T1 + T3, T4 = 150 µs).
  EXPECT_NEAR(t.query_rep_s * 1e6, 262.5, 1e-9);
  EXPECT_NEAR(t.empty_slot_s(t.query_rep_s) * 1e6, 262.5 + 150.0, 1e-9);
  EXPECT_NEAR(t.collided_slot_s(t.query_rep_s) * 1e6, 262.5 + 75.0 + 432.0 + 12.0, 1e-9);
  EXPECT_NEAR(t.query_adjust_s * 1e6, 112.5 + 9 * 37.5, 1e-9);
  EXPECT_NEAR(t.select_s(8) * 1e6, 112.5 + 53 * 37.5, 1e-9);
}

TEST(Gen2LinkTiming, OutOfSpecValuesNameTheKey) {
  auto message = [](const Gen2LinkParams& p) {
    try {
      (void)gen2_link_timing(p, "antennas[0].gen2");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  Gen2LinkParams p;
  p.tari_s = 5e-6;
  EXPECT_NE(message(p).find("antennas[0].gen2.tari_us"), std::string::npos);
  p = {};
  p.blf_hz = 700e3;
  EXPECT_NE(message(p).find("gen2.blf_khz"), std::string::npos);
  p = {};
  p.tari_s = 6.25e-6;
  p.blf_hz = 40e3;  // TRcal 200 µs (DR 8) > 3·RTcal = 56 µs: no divide ratio fits
  EXPECT_NE(message(p).find("no divide ratio fits"), std::string::npos);
  p = {};
  p.data1_tari = 2.5;
  EXPECT_NE(message(p).find("data1_tari"), std::string::npos);
  EXPECT_THROW(parse_gen2_encoding("miller3", "gen2.encoding"), InputError);
  EXPECT_EQ(parse_gen2_encoding("miller8", "x"), Gen2Encoding::kMiller8);
}

}  // namespace
}  // namespace rfidray
