#pragma once
// Real reader logs → rfidray reads: the layouts `rfidray import` understands, the column map, channel plans, and
// the conversion of the reads into readings-CSV rows (io/readings_csv.h) with an antenna pose per read.
//
// Layouts (the column names are matched case-insensitively, ignoring blanks, '_', '-', '.', '(', ')', '/'):
//  - octane: Impinj Octane SDK tag fields and ItemTest exports. The Octane SDK `Tag` has Epc, AntennaPortNumber,
//    ChannelInMhz, PeakRssiInDbm, PhaseAngleInRadians, FirstSeenTime / LastSeenTime (`.Utc`: µs since 1970) —
//    e.g. getAntennaPortNumber(), getPeakRssiInDbm(), getPhaseAngleInRadians() in azaitw/impinjCtrl
//    (src/main/java/com/impinjCtrl/ReportFormat.java); tag.ChannelInMhz, tag.FirstSeenTime.Utc,
//    tag.PhaseAngleInRadians logged by C# Octane SDK programs such as saintnever/impinjR420. ItemTest writes
//    `// Timestamp, EPC, TID, Antenna, RSSI, Frequency, Hostname, PhaseAngle, DopplerFrequency` as a comment
//    line before the rows, an ISO 8601 Timestamp with a UTC offset, Frequency in MHz, PhaseAngle in radians, and a decimal comma in quoted fields under comma-decimal locales
//    (rtb30/Gesture-Recognition, "1 Lat Raise/1_3s_2_2024-07-02_11-22-52.csv").
//  - sllurp: LLRP TagReportData as sllurp decodes it (sllurp/sllurp: sllurp/llrp_decoder.py TVE names
//    AntennaID, FirstSeenTimestampUTC, LastSeenTimestampUTC (µs), PeakRSSI (dBm), ChannelIndex, EPC-96;
//    sllurp/llrp_proto.py: EPC, and the Impinj custom parameters ImpinjRFPhaseAngle (older sllurp: ImpinjPhase,
//    12 bits: 2π/4096 per unit) and ImpinjPeakRSSI (1/100 dBm)). One JSON object per line (also a Python dict
//    repr as `sllurp inventory` prints it, values as 1-element lists as older sllurp gave them, or a
//    {"RO_ACCESS_REPORT": {"TagReportData": [...]}} message), or its CSV form: sllurp/verb/log.py writes
//    timestamp (s),reader,antenna,rssi,epc; csv_recorder.py timestamp_us; scripts that add --impinj-reports
//    columns write phase_angle (12-bit units) and channel_index. In this layout a phase column without a unit in
//    its name is in 12-bit units.
//  - per-stop: a directory of N.csv files, one per antenna stop, header
//    epc,antennaIndex,frequency,time,RSSI,phase,dopplerShift,velocity,x,y,z,angle (x,y,z the antenna position in m,
//    frequency Hz, phase rad, RSSI dBm; a UTF-8 BOM is skipped). When every time is 0, a read gets
//    N · stop_period_s + j · stop_period_s / n (row j of n, so rows keep their order inside their stop);
//    otherwise the files' times are used (seconds unless time_unit says otherwise) and must not decrease.
//  - columns: any CSV through a ColumnMap.
// Units: the ColumnMap's unit wins, then a name that states one (…InRadians, …deg, …InMhz, …khz, …Hz, …_us,
// …_ms, …_s, …SeenTime…, ImpinjPeakRSSI), then the layout's; a frequency without any is taken by magnitude
// (< 1e4: MHz, < 1e7: kHz, else Hz), a numeric time by magnitude as time since 1970 (≥ 1e17 ns, ≥ 1e14 µs, ≥ 1e11 ms, else
// s) and every row must then fall in the same class. ISO 8601 times (2024-07-02T11:32:44.6458200+03:00; no
// offset = UTC) are read as seconds since 1970 UTC. Phase is returned in [0, 2π); the reader never knows the
// distance, so readings get dist = 0.
// Errors are InputError "FILE:LINE: column 'NAME': what" (line 1-based; the header's line for a missing column):
// no EPC / phase / RSSI / time column, no frequency (column, channel + plan, or a default), a non-numeric or
// non-finite value, a unit that does not fit (phase above 2π in radians, above 360 in degrees, not a whole
// number in 12-bit units; a carrier outside 100 MHz–10 GHz; frequency or time magnitudes that change class),
// time going backwards in per-stop data, unknown ColumnMap keys, empty files, a directory without N.csv files.
// Functions are stateless and thread-safe.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "io/readings_csv.h"
#include "io/trajectory_csv.h"

namespace rfidray::io {

enum class LogLayout { kAuto, kOctane, kSllurp, kPerStop, kColumns };
// "auto" | "octane" | "sllurp" | "per-stop" | "columns"; throws InputError naming `field` otherwise.
LogLayout parse_log_layout(const std::string& name, const std::string& field = "--layout");
const char* to_string(LogLayout layout);

// Units a log column may be in. kImpinj12Bit: phase in 2π/4096 steps; kCentiDbm: 1/100 dBm.
enum class LogUnit { kAuto, kRad, kDeg, kImpinj12Bit, kHz, kKhz, kMhz, kS, kMs, kUs, kNs, kDbm, kCentiDbm };

// One field of a log: a column name, or a constant (a number given instead of a name).
struct FieldSource {
  std::string column;
  std::optional<double> constant;
  bool given() const { return !column.empty() || constant.has_value(); }
};

// Where each field is. Fields left empty are found by the layout's usual names.
struct ColumnMap {
  FieldSource epc, phase, frequency, channel, rssi, time, antenna, x, y, z, qx, qy, qz, qw;
  LogUnit phase_unit = LogUnit::kAuto, frequency_unit = LogUnit::kAuto, time_unit = LogUnit::kAuto,
          rssi_unit = LogUnit::kAuto;
};
// "epc=EPC,phase=PhaseAngle,phase_unit=deg,frequency=Freq,frequency_unit=mhz,rssi=RSSI,time=Timestamp,
// time_unit=us,antenna=Port,x=X,y=Y,z=Z" (also channel, qx, qy, qz, qw, rssi_unit). A number instead of a
// column name is a constant (y=0 for a column known to be wrong). Units: phase rad|deg|impinj (12-bit);
// frequency hz|khz|mhz; time s|ms|us|ns; rssi dbm|cdbm. Throws InputError "--columns: ..." on unknown keys
// (with a "did you mean"), bad units, duplicates or a constant EPC / phase.
ColumnMap parse_column_map(const std::string& spec);

// A channel plan: LLRP ChannelIndex i (1-based, as readers number their frequency table) → plan[i-1] Hz.
// "fcc" (FCC part 15: 902.75–927.25 MHz, 50 channels, 500 kHz), "etsi" or "eu" (ETSI EN 302 208: 865.7, 866.3,
// 866.9, 867.5 MHz), "cn920" (China: 920.625–924.375 MHz, 16 channels, 250 kHz), or a comma list of Hz.
std::vector<double> parse_channel_plan(const std::string& spec);

struct RealLogOptions {
  LogLayout layout = LogLayout::kAuto;
  ColumnMap columns;                    // required fields for kColumns; overrides for the others
  std::vector<double> channel_plan_hz;  // for ChannelIndex columns
  double default_frequency_hz = 0.0;    // > 0: the carrier when the log has neither frequency nor channel
  double stop_period_s = 1.0;           // per-stop: time between stops
  bool negate_phase = false;            // readers whose phase falls with distance: φ → −φ
};

// One read as the log gives it, in rfidray's units.
struct RealRead {
  std::string file;
  int line = 0;
  double time_s = 0.0;
  std::string epc;
  std::string antenna;  // "port<N>" for a numeric port column, the text otherwise, "" without one
  double phase_rad = 0.0;     // [0, 2π)
  double rssi_dbm = 0.0;
  double frequency_hz = 0.0;  // > 0
  std::optional<Vec3> position;  // from x,y,z columns
  std::optional<Quat> orientation;  // from qx,qy,qz,qw columns
};

struct RealLog {
  LogLayout layout = LogLayout::kAuto;  // the layout used (detected when auto)
  std::vector<RealRead> reads;          // per-stop: stop then row order; otherwise sorted by time (stable)
  std::vector<std::string> notes;       // what was detected (layout, units, the header line used)
};

// Reads a log file (or, for per-stop, a directory of N.csv files).
RealLog read_real_log(const std::filesystem::path& path, const RealLogOptions& options);

// Where the antenna was for each read: per-read columns, a recorded trajectory, or a fixed pose.
struct AntennaPoseOptions {
  const RecordedTrajectory* trajectory = nullptr;  // not owned
  double trajectory_tolerance_s = 0.0;
  std::optional<Vec3> fixed_position;
  Quat orientation = Quat::Identity();  // for reads without quaternion columns and for fixed_position
  double time_offset_s = 0.0;           // added to every log time (clock offset to the trajectory)
  std::string antenna_name;             // "": the log's antenna ("port<N>") or "antenna"
};

// Readings rows (dist = 0, channel = rank of the carrier among the log's carriers), in the log's order.
// Throws InputError "FILE:LINE: ..." for a read outside the trajectory (by how much), reads without a pose,
// or two pose sources at once.
std::vector<ReadingRow> to_reading_rows(const RealLog& log, const AntennaPoseOptions& options);

}  // namespace rfidray::io
