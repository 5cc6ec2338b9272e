// Real reader logs (io/real_log.h): each layout on small files written here, unit conversions, antenna poses,
// the round trip through the readings CSV, and located errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "core/error.h"
#include "core/units.h"
#include "io/readings_csv.h"
#include "io/real_log.h"
#include "io/trajectory_csv.h"
#include "tests/support/input_error.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::io {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() { return testing::program_scratch_dir("real_log_test"); }

using testing::write_file;
fs::path write(const std::string& name, const std::string& text) { return write_file(temp_dir() / name, text); }

RealLogOptions with_columns(const std::string& spec) {
  RealLogOptions o;
  o.columns = parse_column_map(spec);
  return o;
}

std::string error_of(const fs::path& p, const RealLogOptions& o = {}) {
  return testing::input_error_of([&] { read_real_log(p, o); });
}

bool has_note(const RealLog& log, const std::string& part) {
  for (const std::string& n : log.notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

TEST(ImportRealLog, OctaneDegreesMegahertzMicroseconds) {
  const fs::path p = write("octane_deg.csv",
                           "Epc,AntennaPortNumber,ChannelInMhz,PeakRssiInDbm,PhaseAngleInDegrees,FirstSeenTime\n"
                           "E200 0001,2,865.7,-61.5,90,1700000000250000\n"
                           "E2000002,2,866.3,-60,359.5,1700000000000000\n");
  const RealLog log = read_real_log(p, {});
  EXPECT_EQ(log.layout, LogLayout::kOctane);
  EXPECT_TRUE(has_note(log, "layout octane (auto-detected")) << log.notes[0];
  ASSERT_EQ(log.reads.size(), 2u);
  // Sorted by time: the second row (earlier) comes first.
  const RealRead& a = log.reads[1];
  EXPECT_EQ(a.epc, "E2000001");  // Octane's word grouping removed
  EXPECT_EQ(a.antenna, "port2");
  EXPECT_NEAR(a.phase_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(a.frequency_hz, 865.7e6, 1e-3);
  EXPECT_NEAR(a.time_s, 1700000000.25, 1e-6);
  EXPECT_EQ(a.rssi_dbm, -61.5);
  EXPECT_NEAR(log.reads[0].phase_rad, 359.5 * kPi / 180.0, 1e-12);
  EXPECT_EQ(log.reads[0].line, 3);
}

TEST(ImportRealLog, FrequencyUnitsFromNameAndMagnitude) {
  const std::string h = "EPC,Antenna,Frequency,PeakRssiInDbm,PhaseAngleInRadians,Timestamp\n";
  const RealLog khz = read_real_log(write("khz.csv", h + "A,1,865700,-50,1.25,0.5\n"), {});
  EXPECT_NEAR(khz.reads[0].frequency_hz, 865.7e6, 1e-3);
  EXPECT_TRUE(has_note(khz, "read as kHz (by magnitude)"));
  const RealLog hz = read_real_log(write("hz.csv", h + "A,1,865700000,-50,1.25,0.5\n"), {});
  EXPECT_NEAR(hz.reads[0].frequency_hz, 865.7e6, 1e-3);
  const RealLog mhz = read_real_log(write("mhz.csv", h + "A,1,865.7,-50,1.25,0.5\n"), {});
  EXPECT_NEAR(mhz.reads[0].frequency_hz, 865.7e6, 1e-3);
  EXPECT_NEAR(mhz.reads[0].phase_rad, 1.25, 1e-15);
  EXPECT_EQ(mhz.reads[0].time_s, 0.5);  // small numbers are seconds
  // The name's unit wins over magnitude: 866 "kHz" is no UHF carrier.
  const std::string m = error_of(write("khz_name.csv", "EPC,Antenna,FrequencyKhz,PeakRssiInDbm,PhaseAngleInRadians,"
                                                       "Timestamp\nA,1,866,-50,1,0\n"));
  EXPECT_NE(m.find("khz_name.csv:2: column 'FrequencyKhz': 866 kHz"), std::string::npos) << m;
  // Explicit unit in the column map wins over magnitude.
  RealLogOptions o = with_columns("frequency_unit=mhz");
  EXPECT_NEAR(read_real_log(write("explicit.csv", h + "A,1,902.75,-50,1,0\n"), o).reads[0].frequency_hz, 902.75e6, 1e-3);
}

TEST(ImportRealLog, ItemTestExportWithCommentHeaderDecimalCommaAndIsoTime) {
  const fs::path p = write("itemtest.csv",
                           "// 02/07/2024 11.22.52\n"
                           "// ReaderName=Speedwayr-15-32-c2, AntennaIDs=1, InventoryMode=DualTarget\n"
                           "// Timestamp, EPC, TID, Antenna, RSSI, Frequency, Hostname, PhaseAngle, DopplerFrequency\n"
                           "2024-07-02T11:32:44.6458200+03:00,A1000000,,1,\"-77,5\",\"865,7\",reader,\"0,96\",\n"
                           "2024-07-02T11:32:45.0000000+03:00,A2000000,,1,-70,\"865,7\",reader,\"4,5\",\n");
  const RealLog log = read_real_log(p, {});
  EXPECT_EQ(log.layout, LogLayout::kOctane);
  ASSERT_EQ(log.reads.size(), 2u);
  EXPECT_NEAR(log.reads[0].time_s, 1719909164.64582, 1e-5);  // 08:32:44.64582 UTC
  EXPECT_EQ(log.reads[0].rssi_dbm, -77.5);
  EXPECT_NEAR(log.reads[0].frequency_hz, 865.7e6, 1e-3);
  EXPECT_NEAR(log.reads[0].phase_rad, 0.96, 1e-12);
  EXPECT_EQ(log.reads[0].line, 4);
  EXPECT_EQ(log.reads[1].epc, "A2000000");
  EXPECT_TRUE(has_note(log, "ISO 8601"));
}

TEST(ImportRealLog, SllurpJsonLinesWithChannelPlanImpinjPhaseAndPythonRepr) {
  const fs::path p = write(
      "sllurp.jsonl",
      "{\"EPC-96\": \"30340000000000000000abcd\", \"AntennaID\": 1, \"ChannelIndex\": 3, \"PeakRSSI\": -60,"
      " \"ImpinjRFPhaseAngle\": 1024, \"FirstSeenTimestampUTC\": 1700000000123456}\n"
      "\n"
      "{'EPC-96': b'30340000000000000000abcd', 'AntennaID': (2,), 'ChannelIndex': [4], 'ImpinjPeakRSSI': -6350,"
      " 'ImpinjPhase': 2048, 'FirstSeenTimestampUTC': 1700000000223456, 'Extra': None, 'Flag': True}\n"
      "{\"RO_ACCESS_REPORT\": {\"TagReportData\": [{\"EPCData\": {\"EPC\": \"beef\"}, \"AntennaID\": 1,"
      " \"ChannelIndex\": 1, \"PeakRSSI\": -55, \"ImpinjRFPhaseAngle\": 0, \"FirstSeenTimestampUTC\": 1700000000323456}]}}\n");
  RealLogOptions o;
  o.channel_plan_hz = parse_channel_plan("etsi");
  const RealLog log = read_real_log(p, o);
  EXPECT_EQ(log.layout, LogLayout::kSllurp);
  ASSERT_EQ(log.reads.size(), 3u);
  EXPECT_EQ(log.reads[0].epc, "30340000000000000000abcd");
  EXPECT_EQ(log.reads[0].antenna, "port1");
  EXPECT_NEAR(log.reads[0].phase_rad, kPi / 2, 1e-12);  // 1024 · 2π/4096
  EXPECT_EQ(log.reads[0].frequency_hz, 866.9e6);        // ChannelIndex 3 (1-based) of the ETSI plan
  EXPECT_NEAR(log.reads[0].time_s, 1700000000.123456, 1e-6);
  EXPECT_EQ(log.reads[1].epc, "30340000000000000000abcd");  // b'' bytes of the Python repr
  EXPECT_EQ(log.reads[1].antenna, "port2");
  EXPECT_NEAR(log.reads[1].phase_rad, kPi, 1e-12);  // older sllurp name ImpinjPhase
  EXPECT_EQ(log.reads[1].rssi_dbm, -63.5);          // ImpinjPeakRSSI in 1/100 dBm
  EXPECT_EQ(log.reads[1].frequency_hz, 867.5e6);
  EXPECT_EQ(log.reads[1].line, 3);
  EXPECT_EQ(log.reads[2].epc, "beef");
  EXPECT_EQ(log.reads[2].frequency_hz, 865.7e6);
  EXPECT_EQ(log.reads[2].line, 4);
}

TEST(ImportRealLog, SllurpCsvFormWithFccPlan) {
  const fs::path p = write("sllurp.csv",
                           "timestamp,antenna,rssi,epc,phase_angle,channel_index,doppler_frequency\n"
                           "2025-05-06T10:00:05.123456,1,-35,303435fc,2048,1,250\n"
                           "2025-05-06T10:00:05.223456,1,-36,303435fc,4095,50,250\n");
  RealLogOptions o;
  o.layout = LogLayout::kSllurp;
  o.channel_plan_hz = parse_channel_plan("fcc");
  const RealLog log = read_real_log(p, o);
  ASSERT_EQ(log.reads.size(), 2u);
  EXPECT_NEAR(log.reads[0].time_s, 1746525605.123456, 1e-5);  // no offset: UTC
  EXPECT_TRUE(has_note(log, "no UTC offset given"));
  EXPECT_NEAR(log.reads[0].phase_rad, kPi, 1e-12);
  EXPECT_EQ(log.reads[0].frequency_hz, 902.75e6);
  EXPECT_EQ(log.reads[1].frequency_hz, 927.25e6);
  EXPECT_NEAR(log.reads[1].phase_rad, 4095 * kTwoPi / 4096, 1e-12);
  // Channel 51 is beyond the FCC plan; channel 0 is not an LLRP index.
  std::string m = error_of(write("sllurp_51.csv", "timestamp,antenna,rssi,epc,phase_angle,channel_index\n"
                                                  "1.5,1,-35,303435fc,2048,51\n"),
                           o);
  EXPECT_NE(m.find("sllurp_51.csv:2: column 'channel_index': channel index 51 is beyond"), std::string::npos) << m;
  m = error_of(write("sllurp_0.csv", "timestamp,antenna,rssi,epc,phase_angle,channel_index\n1.5,1,-35,e,2048,0\n"), o);
  EXPECT_NE(m.find("sllurp_0.csv:2: column 'channel_index'"), std::string::npos) << m;
  // Without a plan the channel index cannot become a carrier.
  o.channel_plan_hz.clear();
  m = error_of(p, o);
  EXPECT_NE(m.find("sllurp.csv:1: column 'channel_index': channel indices need a channel plan"), std::string::npos) << m;
  // A 12-bit column holding radians is caught.
  o.channel_plan_hz = parse_channel_plan("fcc");
  m = error_of(write("sllurp_rad.csv", "timestamp,antenna,rssi,epc,phase_angle,channel_index\n1.5,1,-35,e,1.57,1\n"), o);
  EXPECT_NE(m.find("sllurp_rad.csv:2: column 'phase_angle': 1.57 is not a 12-bit phase"), std::string::npos) << m;
}

const std::string kStopHeader = "epc,antennaIndex,frequency,time,RSSI,phase,dopplerShift,velocity,x,y,z,angle\n";

// A per-stop directory: stop n at x = 0.02·(n+1), y = 1.63 (a column known to be wrong), reads of two tags.
fs::path write_stops(const std::string& name, int stops, const std::string& time = "0") {
  const fs::path d = temp_dir() / name;
  fs::remove_all(d);
  for (int n = 0; n < stops; ++n) {
    std::ostringstream s;
    s << "\xEF\xBB\xBF" << kStopHeader;
    const double x = 0.02 * (n + 1);
    s << "1001,1,921125000," << time << ",-46.5,0.8222,0,0," << x << ",1.63,0,-5399.9\n";
    s << "1002,1,920625000," << time << ",-48.5,6.28318530717959,0,0," << x << ",1.63,0,-5399.9\n";
    write_file(d / (std::to_string(n) + ".csv"), s.str());
  }
  write_file(d / "notes.txt", "not a stop file\n");
  return d;
}

TEST(ImportRealLog, PerStopDirectoryGivesEachStopsAntennaPositionAndSkipsTheBom) {
  const fs::path d = write_stops("stops", 12);  // 12 stops: 10.csv must sort after 9.csv
  RealLogOptions o;
  o.stop_period_s = 2.0;
  const RealLog log = read_real_log(d, o);
  EXPECT_EQ(log.layout, LogLayout::kPerStop);
  ASSERT_EQ(log.reads.size(), 24u);
  for (int n = 0; n < 12; ++n) {
    const RealRead& r = log.reads[2 * n];
    ASSERT_TRUE(r.position);
    EXPECT_NEAR(r.position->x(), 0.02 * (n + 1), 1e-15) << n;
    EXPECT_EQ(r.position->y(), 1.63);
    EXPECT_EQ(r.epc, "1001");  // the BOM is not part of the first column's name or value
    EXPECT_EQ(r.time_s, 2.0 * n);
    EXPECT_EQ(log.reads[2 * n + 1].time_s, 2.0 * n + 1.0);  // row 1 of 2, spread over the stop
    EXPECT_EQ(r.antenna, "port1");
  }
  EXPECT_NEAR(log.reads[0].phase_rad, 0.8222, 1e-15);
  EXPECT_EQ(log.reads[1].phase_rad, 0.0);  // 2π as printed (6.28318530717959) wraps to 0
  EXPECT_EQ(log.reads[1].frequency_hz, 920625000.0);
  EXPECT_TRUE(has_note(log, "per-stop times synthesized"));
  // A constant replaces a column known to be wrong.
  o.columns = parse_column_map("y=0");
  EXPECT_EQ(read_real_log(d, o).reads[5].position->y(), 0.0);
  // One stop file on its own: its number from the name.
  const RealLog one = read_real_log(d / "7.csv", {});
  EXPECT_EQ(one.layout, LogLayout::kPerStop);
  EXPECT_EQ(one.reads[0].time_s, 7.0);
}

TEST(ImportRealLog, PerStopUsesNonZeroFileTimesAndRejectsTimeGoingBack) {
  const fs::path d = write_stops("stops_timed", 3, "5");
  write_file(d / "1.csv", kStopHeader + "1001,1,921125000,7.5,-46,0.5,0,0,0.04,0,0,0\n");
  write_file(d / "2.csv", kStopHeader + "1001,1,921125000,9,-46,0.5,0,0,0.06,0,0,0\n");
  const RealLog log = read_real_log(d, {});
  ASSERT_EQ(log.reads.size(), 4u);
  EXPECT_EQ(log.reads[0].time_s, 5.0);
  EXPECT_EQ(log.reads[2].time_s, 7.5);
  EXPECT_EQ(log.reads[3].time_s, 9.0);
  write_file(d / "2.csv", kStopHeader + "1001,1,921125000,6,-46,0.5,0,0,0.06,0,0,0\n");
  const std::string m = error_of(d);
  EXPECT_NE(m.find("2.csv:2: column 'time': time goes backwards"), std::string::npos) << m;
}

TEST(ImportRealLog, ColumnMapWithUnitsAndConstants) {
  const fs::path p = write("mapped.csv",
                           "Tag ID,Port,Freq,Sig,Angle,Timestamp,X,Y,Z\n"
                           "t1,A,902.75,-50,180,1500,1,2,3\n");
  // Names match case-insensitively, ignoring blanks and '_': spelled differently in the map.
  RealLogOptions o = with_columns(
      "epc=tag_id,phase=ANGLE,phase_unit=deg,frequency=Freq,frequency_unit=mhz,rssi=Sig,time=Timestamp,"
      "time_unit=ms,antenna=Port,x=X,y=Y,z=0.5");
  o.layout = LogLayout::kColumns;
  const RealLog log = read_real_log(p, o);
  ASSERT_EQ(log.reads.size(), 1u);
  const RealRead& r = log.reads[0];
  EXPECT_EQ(r.epc, "t1");
  EXPECT_EQ(r.antenna, "A");
  EXPECT_NEAR(r.phase_rad, kPi, 1e-12);
  EXPECT_EQ(r.frequency_hz, 902.75e6);
  EXPECT_EQ(r.time_s, 1.5);
  EXPECT_EQ(*r.position, Vec3(1, 2, 0.5));
  // Quaternion columns (x,y,z,w) give each read its own orientation.
  const RealLog q = read_real_log(
      write("mapped_q.csv", "Tag ID,Port,Freq,Sig,Angle,Timestamp,X,Y,Z,qx,qy,qz,qw\n"
                            "t1,A,902.75,-50,180,1500,1,2,3,0,0,0.7071067811865476,0.7071067811865476\n"),
      o);
  ASSERT_TRUE(q.reads[0].orientation);
  EXPECT_TRUE((*q.reads[0].orientation * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-12));
  EXPECT_EQ(to_reading_rows(q, {})[0].antenna_pose.orientation.coeffs(), q.reads[0].orientation->coeffs());
  // --columns alone picks the columns layout for a header no layout knows.
  RealLogOptions auto_o = o;
  auto_o.layout = LogLayout::kAuto;
  EXPECT_EQ(read_real_log(p, auto_o).layout, LogLayout::kColumns);
  // A column the map names must exist.
  o.columns = parse_column_map("epc=Tag ID,phase=Phase,rssi=Sig,time=Timestamp,frequency=Freq");
  const std::string m = error_of(p, o);
  EXPECT_NE(m.find("mapped.csv:1: column 'Phase' (--columns phase=Phase): not in the header"), std::string::npos) << m;
}

TEST(ImportRealLog, ColumnMapAndChannelPlanErrors) {
  auto error = [](auto&& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string m = error([] { parse_column_map("epc=EPC,phse=Phase"); });
  EXPECT_NE(m.find("--columns: unknown key 'phse' (did you mean 'phase'?)"), std::string::npos) << m;
  EXPECT_NE(error([] { parse_column_map("phase_unit=grad"); }).find("rad, deg or impinj"), std::string::npos);
  EXPECT_NE(error([] { parse_column_map("phase"); }).find("not KEY=VALUE"), std::string::npos);
  EXPECT_NE(error([] { parse_column_map("x=X,x=Y"); }).find("given twice"), std::string::npos);
  EXPECT_NE(error([] { parse_channel_plan("mars"); }).find("--channel-plan: 'mars'"), std::string::npos);
  EXPECT_EQ(parse_channel_plan("cn920").size(), 16u);
  EXPECT_EQ(parse_channel_plan("cn920")[15], 924.375e6);
  EXPECT_EQ(parse_channel_plan("866.3e6, 865.7e6"), (std::vector<double>{866.3e6, 865.7e6}));
  EXPECT_NE(error([] { parse_log_layout("impinj"); }).find("--layout"), std::string::npos);
}

TEST(ImportRealLog, BadValuesNameFileLineAndColumn) {
  const std::string h = "Epc,AntennaPortNumber,ChannelInMhz,PeakRssiInDbm,PhaseAngleInRadians,FirstSeenTime\n";
  const std::string ok = "E1,1,865.7,-50,1.0,1700000000000000\n";
  std::string m = error_of(write("no_phase.csv", "Epc,AntennaPortNumber,ChannelInMhz,PeakRssiInDbm,FirstSeenTime\n"
                                                 "E1,1,865.7,-50,1700000000000000\n"));
  EXPECT_NE(m.find("no_phase.csv:1: column 'phase': no phase column"), std::string::npos) << m;
  m = error_of(write("word.csv", h + ok + "E1,1,865.7,loud,1.0,1700000000000000\n"));
  EXPECT_NE(m.find("word.csv:3: column 'PeakRssiInDbm': not a number ('loud')"), std::string::npos) << m;
  m = error_of(write("nan.csv", h + ok + "E1,1,865.7,-50,nan,1700000000000000\n"));
  EXPECT_NE(m.find("nan.csv:3: column 'PhaseAngleInRadians': not finite"), std::string::npos) << m;
  m = error_of(write("rad_big.csv", h + ok + "E1,1,865.7,-50,57.3,1700000000000000\n"));
  EXPECT_NE(m.find("rad_big.csv:3: column 'PhaseAngleInRadians': 57.3 is above 2pi"), std::string::npos) << m;
  const std::string hd = "Epc,AntennaPortNumber,ChannelInMhz,PeakRssiInDbm,PhaseAngleDeg,FirstSeenTime\n";
  m = error_of(write("deg_big.csv", hd + "E1,1,865.7,-50,361,1700000000000000\n"));
  EXPECT_NE(m.find("deg_big.csv:2: column 'PhaseAngleDeg': 361 is outside [-180, 360] degrees"), std::string::npos) << m;
  // Degrees that all happen to be ≤ 2π are fine.
  EXPECT_NEAR(read_real_log(write("deg_small.csv", hd + "E1,1,865.7,-50,6,1700000000000000\n"), {}).reads[0].phase_rad,
              6 * kPi / 180, 1e-12);
  m = error_of(write("mixed_f.csv", "EPC,Antenna,Frequency,PeakRssiInDbm,PhaseAngleInRadians,Timestamp\n"
                                    "A,1,865.7,-50,1,0\nA,1,866300000,-50,1,1\n"));
  EXPECT_NE(m.find("mixed_f.csv:3: column 'Frequency': 866300000 looks like Hz but earlier values (" +
                   (temp_dir() / "mixed_f.csv").string() + ":2) like MHz"),
            std::string::npos)
      << m;
  m = error_of(write("mixed_t.csv", "EPC,Antenna,Frequency,PeakRssiInDbm,PhaseAngleInRadians,Timestamp\n"
                                    "A,1,865.7,-50,1,1700000000000\nA,1,865.7,-50,1,1700000000\n"));
  EXPECT_NE(m.find("mixed_t.csv:3: column 'Timestamp':"), std::string::npos) << m;
  EXPECT_NE(m.find("mixed units"), std::string::npos) << m;
  m = error_of(write("cdbm.csv", h + "E1,1,865.7,-6350,1.0,1700000000000000\n"));
  EXPECT_NE(m.find("cdbm.csv:2: column 'PeakRssiInDbm': -6350 is not an RSSI"), std::string::npos) << m;
  m = error_of(write("fields.csv", h + "E1,1,865.7\n"));
  EXPECT_NE(m.find("fields.csv:2: expected 6 fields"), std::string::npos) << m;
  m = error_of(write("no_freq.csv", "Epc,PeakRssiInDbm,PhaseAngleInRadians,FirstSeenTime\nE,-50,1,0\n"));
  EXPECT_NE(m.find("no_freq.csv:1: column 'frequency': no frequency or channel column"), std::string::npos) << m;
  RealLogOptions f;
  f.default_frequency_hz = 866.9e6;
  EXPECT_EQ(read_real_log(temp_dir() / "no_freq.csv", f).reads[0].frequency_hz, 866.9e6);
  m = error_of(write("unknown.csv", "a,b,c\n1,2,3\n"));
  EXPECT_NE(m.find("unknown.csv:1: cannot tell the layout"), std::string::npos) << m;
  m = error_of(write("bad.jsonl", "{\"EPC\": \"a\",\n"));
  EXPECT_NE(m.find("bad.jsonl:1: not a JSON object"), std::string::npos) << m;
  EXPECT_NE(error_of(write("empty.csv", "")).find("empty.csv: empty file"), std::string::npos);
  EXPECT_NE(error_of(write("blank.csv", "\n  \n")).find("blank.csv: empty file"), std::string::npos);
  EXPECT_NE(error_of(write("header.csv", h)).find("header.csv: empty file (a header but no reads)"), std::string::npos);
  const fs::path empty_dir = temp_dir() / "no_stops";
  fs::create_directories(empty_dir);
  write_file(empty_dir / "readme.txt", "x");
  EXPECT_NE(error_of(empty_dir).find("no_stops: no N.csv files"), std::string::npos);
  EXPECT_NE(error_of(temp_dir() / "missing.csv").find("no such file"), std::string::npos);
}

TEST(ImportRealLog, TrajectoryPosesAtReadTimesAndReadsOutsideTheSpan) {
  const std::string h = "EPC,Antenna,Frequency,PeakRssiInDbm,PhaseAngleInRadians,Timestamp\n";
  const RealLog log = read_real_log(
      write("traj_log.csv", h + "A,1,865.7,-50,1,10.5\nB,2,866.3,-51,2,11\nA,1,866.3,-52,3,12\n"), {});
  const RecordedTrajectory traj("traj.csv", {{10.0, Pose{Vec3(0, 0, 1), Quat::Identity()}, 2},
                                             {12.0, Pose{Vec3(2, 0, 1), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()))}, 3}});
  AntennaPoseOptions o;
  o.trajectory = &traj;
  const std::vector<ReadingRow> rows = to_reading_rows(log, o);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_TRUE(rows[0].antenna_pose.position.isApprox(Vec3(0.5, 0, 1), 1e-12));
  EXPECT_TRUE(rows[1].antenna_pose.position.isApprox(Vec3(1, 0, 1), 1e-12));
  EXPECT_LT(rows[1].antenna_pose.orientation.angularDistance(Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitZ()))), 1e-12);
  EXPECT_EQ(rows[0].antenna, "port1");
  EXPECT_EQ(rows[1].antenna, "port2");
  EXPECT_EQ(rows[0].distance_m, 0.0);
  EXPECT_EQ(rows[0].hop_index, 0);  // rank of 865.7 MHz among the log's carriers
  EXPECT_EQ(rows[1].hop_index, 1);
  // A clock offset moves the reads; the last one then lies 0.25 s past the trajectory.
  o.time_offset_s = 0.25;
  try {
    to_reading_rows(log, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("traj_log.csv:4: read outside the trajectory: time 12.25 s is 0.25 s after the end"),
              std::string::npos)
        << m;
  }
  o.trajectory_tolerance_s = 0.3;
  EXPECT_EQ(to_reading_rows(log, o)[2].antenna_pose.position, Vec3(2, 0, 1));
  // Two ports with one --antenna-name would merge their histories.
  o.antenna_name = "reader";
  EXPECT_THROW(to_reading_rows(log, o), InputError);
  // No pose at all, or two sources.
  AntennaPoseOptions none;
  EXPECT_THROW(to_reading_rows(log, none), InputError);
  AntennaPoseOptions both;
  both.trajectory = &traj;
  both.fixed_position = Vec3(0, 0, 0);
  EXPECT_THROW(to_reading_rows(log, both), InputError);
}

TEST(ImportRealLog, RoundTripThroughTheReadingsCsv) {
  const RealLog log = read_real_log(write_stops("stops_rt", 3), {});
  AntennaPoseOptions o;
  o.orientation = quat_from_rpy(Vec3(0, 0, kPi / 2));  // facing +y
  o.antenna_name = "adarf";
  const std::vector<ReadingRow> rows = to_reading_rows(log, o);
  const fs::path p = temp_dir() / "round_trip.csv";
  {
    std::ofstream out(p);
    write_readings_csv(out, rows);
  }
  const std::vector<ReadingRow> back = read_readings_csv(p);
  ASSERT_EQ(back.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_NEAR(back[i].time_s, rows[i].time_s, 1e-6);
    EXPECT_TRUE(back[i].antenna_pose.position.isApprox(rows[i].antenna_pose.position, 1e-6));
    EXPECT_LT(back[i].antenna_pose.orientation.angularDistance(rows[i].antenna_pose.orientation), 1e-8);
    EXPECT_EQ(back[i].tag, rows[i].tag);
    EXPECT_EQ(back[i].distance_m, 0.0);
    EXPECT_NEAR(back[i].phase_rad, rows[i].phase_rad, 1e-6);
    EXPECT_GE(back[i].phase_rad, 0.0);
    EXPECT_LT(back[i].phase_rad, kTwoPi);
    EXPECT_EQ(back[i].rssi, rows[i].rssi);
    EXPECT_EQ(back[i].antenna, "adarf");
    EXPECT_EQ(back[i].frequency_hz, rows[i].frequency_hz);
    EXPECT_EQ(back[i].hop_index, rows[i].hop_index);
  }
  // The antenna's boresight (+X) points along +y.
  EXPECT_TRUE((back[0].antenna_pose.orientation * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-8));
}

}  // namespace
}  // namespace rfidray::io
