// Issue #12: input ranges checked where the data enters (file:line, field), writers that refuse non-finite
// values, and atomic output files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "core/simulation.h"
#include "io/atomic_file.h"
#include "io/readings_csv.h"
#include "io/scenario_yaml.h"
#include "tests/support/input_error.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::io {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::string& text) {
  return testing::input_error_of([&] { parse_scenario(text, "s.yaml"); });
}

std::string antenna_with(const std::string& keys) {
  return "duration_s: 1\nantennas:\n  - name: a1\n    position: [0, 0, 1]\n" + keys + "tags:\n  - {name: t0, position: [3, 0, 1.5]}\n";
}

TEST(InputRanges, ReaderValuesOutOfTheirPhysicalRangeNameFileLineAndField) {
  const struct {
    std::string keys, field, line = "s.yaml:3:";
  } cases[] = {
      {"    frequency: 1e-300\n", "antennas[0].frequency"},
      {"    frequency: 2e11\n", "antennas[0].frequency"},
      {"    frequencies_hz: [866e6, 1e-3]\n", "antennas[0].frequency[1]"},
      {"    tx_power_dbm: 1e308\n", "antennas[0].tx_power_dbm"},
      {"    sensitivity_dbm: -500\n", "antennas[0].sensitivity_dbm"},
      {"    noise_rssi_db: 1e308\n", "antennas[0].noise_rssi_db"},
      {"    noisephi: 1e308\n", "antennas[0].noisephi"},
      {"    gain_dbi: 1e5\n", "gain_dbi"},
      {"    pattern: {kind: patch, gain_dbi: 1e308}\n", "antennas[0].pattern.gain_dbi", "s.yaml:5:"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(antenna_with(c.keys));
    EXPECT_NE(e.find(c.line), std::string::npos) << c.keys << " -> " << e;
    EXPECT_NE(e.find(c.field), std::string::npos) << c.keys << " -> " << e;
    EXPECT_EQ(e.find("inf"), std::string::npos) << e;
  }
  // Legitimate values still parse.
  EXPECT_EQ(error_of(antenna_with("    frequency: 2.45e9\n    tx_power_dbm: 30\n    noise_rssi_db: 2\n")), "");
}

TEST(InputRanges, TagAndPositionRanges) {
  std::string e = error_of("duration_s: 1\nantennas:\n  - {name: a1, position: [0, 0, 1]}\n"
                           "tags:\n  - {name: t0, position: [3, 0, 1.5], gain_dbi: -1e308}\n");
  EXPECT_NE(e.find("s.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("tags[0].gain_dbi"), std::string::npos) << e;
  e = error_of("duration_s: 1\nantennas:\n  - {name: a1, position: [0, 1e300, 1]}\n");
  EXPECT_NE(e.find("s.yaml:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("antennas[0].position"), std::string::npos) << e;
  // UTM-sized positions are fine.
  EXPECT_EQ(error_of("duration_s: 1\nantennas:\n  - {name: a1, position: [512345, 5012345, 1]}\n"), "");
}

TEST(InputRanges, HugeDurationIsRefusedWithTheTickCount) {
  const Scenario s = parse_scenario("duration_s: 1e20\nantennas:\n  - {name: a1, position: [0, 0, 1], update_rate: 10}\n"
                                    "tags:\n  - {name: t0, position: [3, 0, 1.5]}\n",
                                    "d.yaml");
  const IdealChannel ideal;
  try {
    simulate(s, ideal);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("d.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("duration_s"), std::string::npos) << m;
    EXPECT_NE(m.find("1e+21 ticks"), std::string::npos) << m;
  }
}

// fuzz finding: a readings CSV with an antenna at 1e308 m made localize allocate without bound (exit 1).
TEST(ReadingsReader, CoordinatesBeyondTheRangeNameFileLineAndColumn) {
  const fs::path dir = fs::temp_directory_path() / "rfidray_readings_range_test";
  fs::create_directories(dir);
  {
    std::ofstream out(dir / "r.csv");
    out << kReadingsHeader << "\n0,0,0,0,0,0,0,1,t,1,1,-60,a,865700000,0\n0.1,-1e308,0,0,0,0,0,1,t,1,1,-60,a,865700000,0\n";
    std::ofstream truth(dir / "t.csv");
    truth << "name,x,y,z\nt,0,2e8,0\n";
  }
  for (const auto& [file, expected] : {std::pair{"r.csv", "r.csv:3: column 'posx': -1e308 m is outside"},
                                       std::pair{"t.csv", "t.csv:2: column 'y': 2e8 m is outside"}}) {
    try {
      if (std::string(file) == "r.csv") read_readings_csv(dir / file);
      else read_truth_csv(dir / file);
      ADD_FAILURE() << file << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  fs::remove_all(dir);
}

TEST(ReadingsWriter, RefusesANonFiniteValueNamingTheColumn) {
  const Scenario s = parse_scenario(antenna_with(""), "w.yaml");
  AntennaResult r;
  ReadRecord rec;
  rec.antenna_pose = Pose{};
  rec.distance_m = 3.0;
  rec.frequency_hz = 866e6;
  rec.reading.read = true;
  rec.reading.phase_rad = 1.0;
  rec.reading.rssi_dbm = INFINITY;
  r.reads.push_back(rec);
  std::ostringstream out;
  try {
    write_readings_csv(out, s, 0, r);
    FAIL() << "wrote " << out.str();
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("column 'rssi'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(out.str().find("inf"), std::string::npos);
}

class AtomicFile : public ::testing::Test {
 protected:
  size_t entries() const { return static_cast<size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())); }
  const testing::ScratchDir scratch_{testing::ScratchDir::current_test_name("atomic")};
  const fs::path dir_ = scratch_.path();
};

TEST_F(AtomicFile, WritesCompleteFilesAndNothingWhenTheBodyFails) {
  write_file_atomic(dir_ / "ok.csv", [](std::ostream& o) { o << "a,b\n1,2\n"; });
  std::ifstream in(dir_ / "ok.csv");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "a,b\n1,2\n");
  EXPECT_EQ(entries(), 1u);
  // A body that fails half-way: no file under the final name, no temporary left, an old file kept.
  EXPECT_THROW(write_file_atomic(dir_ / "bad.csv",
                                 [](std::ostream& o) {
                                   o << "a,b\n";
                                   throw std::logic_error("boom");
                                 }),
               std::logic_error);
  EXPECT_FALSE(fs::exists(dir_ / "bad.csv"));
  EXPECT_THROW(write_file_atomic(dir_ / "ok.csv", [](std::ostream&) { throw std::logic_error("boom"); }), std::logic_error);
  EXPECT_EQ(entries(), 1u);
  in.close();
  in.open(dir_ / "ok.csv");
  std::stringstream again;
  again << in.rdbuf();
  EXPECT_EQ(again.str(), "a,b\n1,2\n");
}

TEST_F(AtomicFile, RefusesNonRegularOutputsAndPathsInsideAFile) {
  EXPECT_THROW(write_file_atomic("/dev/null", [](std::ostream& o) { o << "x"; }), InputError);
  EXPECT_THROW(write_file_atomic(dir_, [](std::ostream& o) { o << "x"; }), InputError);
  std::ofstream(dir_ / "plain") << "x";
  try {
    write_file_atomic(dir_ / "plain" / "f.csv", [](std::ostream& o) { o << "x"; });
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plain/f.csv"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rfidray::io
