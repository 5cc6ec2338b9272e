// `rfidray import` end to end: logs written here in each layout, the readings CSV it writes, `localize` on it,
// and exit status 2 with FILE:LINE and the column for bad input (leaving no output file behind).
#include <gtest/gtest.h>

#include "tests/support/run_rfidray.h"
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/units.h"
#include "io/readings_csv.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::io {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() { return testing::program_scratch_dir("import_cli_test"); }

using testing::write_file;

// Runs rfidray with `args`; returns stdout+stderr, sets the exit code.
std::string rfidray(const std::string& args, int& exit_code) {
  const rfidray::testing::CliResult r = rfidray::testing::run_rfidray(args);
  exit_code = r.status;
  return r.output;
}

const Vec3 kTag(0.9, 0.8, 0.0);
const std::array<double, 3> kCarriersHz{920.625e6, 922.125e6, 924.125e6};

double true_phase(const Vec3& antenna, double f_hz, double offset) {
  return wrap_to_2pi(4.0 * kPi * (kTag - antenna).norm() * f_hz / kSpeedOfLight_m_s + offset);
}

// A per-stop directory as the AdaRF set has it: 90 stops 2 cm apart along x, the tag read on three carriers at
// each stop, y written as 1.63 (a column the set documents as invalid), times all 0, a BOM before the header.
fs::path write_stop_dir(const std::string& name) {
  const fs::path d = temp_dir() / name;
  fs::remove_all(d);
  for (int n = 0; n < 90; ++n) {
    std::ostringstream s;
    s << std::setprecision(17) << "\xEF\xBB\xBF"
      << "epc,antennaIndex,frequency,time,RSSI,phase,dopplerShift,velocity,x,y,z,angle\n";
    const Vec3 antenna(0.02 * n, 0.0, 0.0);
    for (size_t k = 0; k < kCarriersHz.size(); ++k)
      s << "100000000000000000000001,1," << kCarriersHz[k] << ",0,-48.5,"
        << true_phase(antenna, kCarriersHz[k], 0.3 + k) << ",0,0," << antenna.x() << ",1.63,0,-5399.9\n";
    write_file(d / (std::to_string(n) + ".csv"), s.str());
  }
  return d;
}

TEST(ImportCli, PerStopDirectoryImportsAndLocalizes) {
  const fs::path d = write_stop_dir("stops");
  const fs::path out = temp_dir() / "stops_readings.csv", tags = temp_dir() / "stops_tags.csv";
  int code = 0;
  const std::string log = rfidray("import " + d.string() + " -o " + out.string() + " --tags-out " + tags.string() +
                                      " --columns y=0 --antenna-rpy 0,0,90 --stop-period-s 0.5",
                                  code);
  ASSERT_EQ(code, 0) << log;
  EXPECT_NE(log.find("imported 270 reads, 1 tags, 3 carriers (920.625 .. 924.125 MHz), 1 antenna (port1), "
                     "time 0.000 .. 44.833 s (span 44.833 s), layout per-stop -> "),
            std::string::npos)
      << log;
  const std::vector<ReadingRow> rows = read_readings_csv(out);
  ASSERT_EQ(rows.size(), 270u);
  for (const ReadingRow& r : rows) {
    EXPECT_EQ(r.distance_m, 0.0);
    EXPECT_EQ(r.antenna_pose.position.y(), 0.0);
    EXPECT_TRUE((r.antenna_pose.orientation * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-8));
    EXPECT_NEAR(r.phase_rad, true_phase(r.antenna_pose.position, r.frequency_hz, 0.3 + r.hop_index), 2e-6);
  }
  EXPECT_NEAR(rows[3 * 40].antenna_pose.position.x(), 0.8, 1e-9);  // stop 40
  EXPECT_EQ(rows[3 * 40].time_s, 20.0);
  std::ifstream t(tags);
  std::string header, line;
  std::getline(t, header);
  std::getline(t, line);
  EXPECT_EQ(header, "name,reads,first_time,last_time,max_rssi");
  EXPECT_EQ(line.rfind("100000000000000000000001,270,0,", 0), 0u) << line;

  write_file(temp_dir() / "truth.csv", "name,x,y,z\n100000000000000000000001,0.9,0.8,0\n");
  const std::string loc = rfidray("localize " + out.string() + " --truth " + (temp_dir() / "truth.csv").string() +
                                      " --height-known --mirror-prior truth --method nlls --json",
                                  code);
  ASSERT_EQ(code, 0) << loc;
  const nlohmann::json j = nlohmann::json::parse(loc);
  ASSERT_EQ(j["results"].size(), 1u);
  ASSERT_EQ(j["results"][0]["status"], "ok") << j.dump();
  EXPECT_LT(j["results"][0]["error_m"].get<double>(), 0.01) << j.dump();
}

TEST(ImportCli, OctaneLogWithTrajectoryInterpolatesPoses) {
  const fs::path d = temp_dir();
  write_file(d / "octane.csv",
        "Epc,AntennaPortNumber,ChannelInMhz,PeakRssiInDbm,PhaseAngleInRadians,FirstSeenTime\n"
        "E1,1,865.7,-50,1.5,1000500000\n"
        "E2,1,866.3,-51,2.5,1001000000\n");
  write_file(d / "traj.csv", "time,x,y,z,qx,qy,qz,qw\n1000,0,0,1,0,0,0,1\n1001,1,0,1,0,0,0,1\n1002,1,0,1,0,0,0,1\n");
  int code = 0;
  const std::string log = rfidray("import " + (d / "octane.csv").string() + " --trajectory " + (d / "traj.csv").string() +
                                      " -o " + (d / "octane_readings.csv").string() + " --antenna-name mobile",
                                  code);
  ASSERT_EQ(code, 0) << log;
  EXPECT_NE(log.find("layout octane (auto-detected from the header: column 'PhaseAngleInRadians')"), std::string::npos)
      << log;
  const std::vector<ReadingRow> rows = read_readings_csv(d / "octane_readings.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NEAR(rows[0].time_s, 1000.5, 1e-9);
  EXPECT_NEAR(rows[0].antenna_pose.position.x(), 0.5, 1e-9);
  EXPECT_EQ(rows[0].antenna_pose.position.z(), 1.0);
  EXPECT_EQ(rows[0].antenna, "mobile");
  EXPECT_EQ(rows[0].frequency_hz, 865.7e6);
  EXPECT_EQ(rows[1].hop_index, 1);
  EXPECT_NEAR(rows[1].antenna_pose.position.x(), 1.0, 1e-9);
}

struct BadCase {
  std::string name;
  std::string args;      // after "import"; {d} is the temp dir
  std::string expected;  // part of the message
};

TEST(ImportCli, BadInputExitsTwoWithFileLineAndColumnAndWritesNothing) {
  const fs::path d = temp_dir() / "bad";
  fs::create_directories(d);
  const std::string h = "Epc,AntennaPortNumber,ChannelInMhz,PeakRssiInDbm,PhaseAngleInRadians,FirstSeenTime\n";
  write_file(d / "word.csv", h + "E1,1,865.7,-50,1.0,1000000000\nE1,1,865.7,-50,one,1000000001\n");
  write_file(d / "inf.csv", h + "E1,1,865.7,-50,1.0,1000000000\nE1,1,865.7,inf,1.0,1000000001\n");
  write_file(d / "deg_as_rad.csv", h + "E1,1,865.7,-50,90,1000000000\n");
  write_file(d / "no_phase.csv", "Epc,AntennaPortNumber,ChannelInMhz,PeakRssiInDbm,FirstSeenTime\nE1,1,865.7,-50,1\n");
  write_file(d / "empty.csv", "");
  write_file(d / "ok.csv", h + "E1,1,865.7,-50,1.0,1000000000\nE1,1,865.7,-50,1.0,1003000000\n");
  write_file(d / "traj_back.csv", "time,x,y,z\n0,0,0,0\n2000,1,0,0\n1999,1,0,0\n");
  write_file(d / "traj_short.csv", "time,x,y,z\n999,0,0,0\n1001,1,0,0\n");
  fs::create_directories(d / "no_stops");
  write_file(d / "stops_back" / "0.csv", "epc,antennaIndex,frequency,time,RSSI,phase,dopplerShift,velocity,x,y,z,angle\n"
                                    "E,1,921125000,5,-46,0.5,0,0,0,0,0,0\n");
  write_file(d / "stops_back" / "1.csv", "epc,antennaIndex,frequency,time,RSSI,phase,dopplerShift,velocity,x,y,z,angle\n"
                                    "E,1,921125000,4,-46,0.5,0,0,0.02,0,0,0\n");
  const std::string ds = d.string();
  const std::vector<BadCase> cases{
      {"non-numeric", ds + "/word.csv --antenna-position 0,0,0", "word.csv:3: column 'PhaseAngleInRadians': not a number"},
      {"non-finite", ds + "/inf.csv --antenna-position 0,0,0", "inf.csv:3: column 'PeakRssiInDbm': not finite"},
      {"mixed units", ds + "/deg_as_rad.csv --antenna-position 0,0,0",
       "deg_as_rad.csv:2: column 'PhaseAngleInRadians': 90 is above 2pi"},
      {"no phase", ds + "/no_phase.csv --antenna-position 0,0,0", "no_phase.csv:1: column 'phase': no phase column"},
      {"empty file", ds + "/empty.csv --antenna-position 0,0,0", "empty.csv: empty file"},
      {"unknown --columns key", ds + "/ok.csv --antenna-position 0,0,0 --columns phse=X",
       "--columns: unknown key 'phse' (did you mean 'phase'?)"},
      {"trajectory backwards", ds + "/ok.csv --trajectory " + ds + "/traj_back.csv",
       "traj_back.csv:4: column 'time': time goes backwards"},
      {"outside the trajectory", ds + "/ok.csv --trajectory " + ds + "/traj_short.csv",
       "ok.csv:3: read outside the trajectory: time 1003 s is 2 s after the end"},
      {"no pose", ds + "/ok.csv", "no antenna pose"},
      {"no stop files", ds + "/no_stops", "no_stops: no N.csv files"},
      {"per-stop time backwards", ds + "/stops_back", "1.csv:2: column 'time': time goes backwards"},
      {"bad layout", ds + "/ok.csv --layout impinj", "--layout"},
  };
  for (const BadCase& c : cases) {
    const fs::path out = d / "out.csv";
    int code = 0;
    const std::string log = rfidray("import " + c.args + " -o " + out.string(), code);
    EXPECT_EQ(code, 2) << c.name << ": " << log;
    EXPECT_NE(log.find(c.expected), std::string::npos) << c.name << ": " << log;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
  // A failure leaves neither the output nor a temporary file; a success leaves only the output.
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename().string().find(".out.csv.tmp"), std::string::npos) << e.path();
  int code = 0;
  const std::string log = rfidray("import " + ds + "/ok.csv --antenna-position 1,2,3 -o " + ds + "/out.csv", code);
  ASSERT_EQ(code, 0) << log;
  EXPECT_TRUE(fs::exists(d / "out.csv"));
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  EXPECT_EQ(read_readings_csv(d / "out.csv")[1].antenna_pose.position, Vec3(1, 2, 3));
}

TEST(ImportCli, OutputIsByteIdenticalAcrossRuns) {
  const fs::path d = write_stop_dir("stops_twice");
  int code = 0;
  for (const char* name : {"a.csv", "b.csv"}) {
    const std::string log = rfidray("import " + d.string() + " -q -o " + (temp_dir() / name).string(), code);
    ASSERT_EQ(code, 0) << log;
  }
  std::ifstream a(temp_dir() / "a.csv"), b(temp_dir() / "b.csv");
  std::stringstream sa, sb;
  sa << a.rdbuf();
  sb << b.rdbuf();
  EXPECT_EQ(sa.str(), sb.str());
  EXPECT_EQ(sa.str().find("nan"), std::string::npos);
  EXPECT_EQ(sa.str().rfind(std::string(kReadingsHeader) + "\n", 0), 0u);
}

}  // namespace
}  // namespace rfidray::io
