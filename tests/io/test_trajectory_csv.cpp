// Recorded antenna trajectories (io/trajectory_csv.h): linear positions, slerp orientations, stop-and-go
// samples, the span check, and located errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/error.h"
#include "core/units.h"
#include "io/trajectory_csv.h"
#include "tests/support/input_error.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::io {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() { return testing::program_scratch_dir("trajectory_test"); }

fs::path write(const std::string& name, const std::string& text) { return testing::write_file(temp_dir() / name, text); }

std::string error_of(const fs::path& p) {
  return testing::input_error_of([&] { read_trajectory_csv(p); });
}

TEST(TrajectoryCsv, PositionsAreLinearInTimeAndSamplesAreExact) {
  const RecordedTrajectory t = read_trajectory_csv(
      write("linear.csv", "time,x,y,z,qx,qy,qz,qw\n10,0,0,0,0,0,0,1\n12,2,4,6,0,0,0,1\n13,2,4,7,0,0,0,1\n"));
  EXPECT_EQ(t.start_s(), 10.0);
  EXPECT_EQ(t.end_s(), 13.0);
  EXPECT_TRUE(t.pose_at(10.5).position.isApprox(Vec3(0.5, 1.0, 1.5), 1e-12));
  EXPECT_TRUE(t.pose_at(12.5).position.isApprox(Vec3(2.0, 4.0, 6.5), 1e-12));
  EXPECT_EQ(t.pose_at(12.0).position, Vec3(2, 4, 6));
  EXPECT_EQ(t.pose_at(13.0).position, Vec3(2, 4, 7));
}

TEST(TrajectoryCsv, SlerpHalfwayIsTheAnalyticRotation) {
  // Identity → 90° about z (written with the opposite sign, -q: the same rotation): halfway is 45° about z.
  const double s = std::sin(kPi / 4), c = std::cos(kPi / 4);
  const RecordedTrajectory t = read_trajectory_csv(write(
      "slerp.csv", "time,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n1,0,0,0,0,0,-" + std::to_string(s) + ",-" +
                       std::to_string(c) + "\n"));
  const Quat half(Eigen::AngleAxisd(kPi / 4, Vec3::UnitZ()));
  EXPECT_LT(t.pose_at(0.5).orientation.angularDistance(half), 1e-6);
  const Quat quarter(Eigen::AngleAxisd(kPi / 8, Vec3::UnitZ()));
  EXPECT_LT(t.pose_at(0.25).orientation.angularDistance(quarter), 1e-6);
  // A general axis: 120° about (1,1,1)/√3 — halfway is 60° about the same axis.
  const Quat q1(Eigen::AngleAxisd(2 * kPi / 3, Vec3(1, 1, 1).normalized()));
  const RecordedTrajectory g("code", {{0.0, Pose{Vec3::Zero(), Quat::Identity()}, 0}, {2.0, Pose{Vec3::Zero(), q1}, 0}});
  const Quat expected(Eigen::AngleAxisd(kPi / 3, Vec3(1, 1, 1).normalized()));
  EXPECT_LT(g.pose_at(1.0).orientation.angularDistance(expected), 1e-12);
  EXPECT_NEAR(g.pose_at(1.0).orientation.norm(), 1.0, 1e-15);
}

TEST(TrajectoryCsv, StopAndGoAndRepeatedSamplesInterpolateWithoutDividingByZero) {
  // The robot stops at (1,0,0) from t = 1 to t = 2 (three samples there, two at t = 2), then drives on.
  const RecordedTrajectory t = read_trajectory_csv(
      write("stop.csv", "time,x,y,z\n0,0,0,0\n1,1,0,0\n1.5,1,0,0\n2,1,0,0\n2,1,0,0\n3,3,0,0\n"));
  for (double time : {1.0, 1.25, 1.5, 1.75, 2.0}) {
    const Pose p = t.pose_at(time);
    EXPECT_EQ(p.position, Vec3(1, 0, 0)) << time;
    EXPECT_TRUE(p.orientation.coeffs().allFinite());
  }
  EXPECT_TRUE(t.pose_at(2.5).position.isApprox(Vec3(2, 0, 0), 1e-12));
  EXPECT_TRUE(t.pose_at(0.5).position.isApprox(Vec3(0.5, 0, 0), 1e-12));
  // Without quaternion columns the orientation is the identity.
  EXPECT_EQ(t.pose_at(2.5).orientation.coeffs(), Quat::Identity().coeffs());
}

TEST(TrajectoryCsv, TimesOutsideTheSpanSayByHowMuch) {
  const RecordedTrajectory t = read_trajectory_csv(write("span.csv", "time,x,y,z\n10,0,0,0\n12,2,0,0\n"));
  try {
    t.pose_at(12.5);
    FAIL() << "no error after the end";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("0.5 s after the end"), std::string::npos) << m;
    EXPECT_NE(m.find("span.csv: 10 .. 12 s"), std::string::npos) << m;
  }
  try {
    t.pose_at(9.75);
    FAIL() << "no error before the start";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0.25 s before the start"), std::string::npos) << e.what();
  }
  // Within the tolerance the nearest end holds.
  EXPECT_EQ(t.pose_at(12.5, 0.6).position, Vec3(2, 0, 0));
  EXPECT_EQ(t.pose_at(9.75, 0.3).position, Vec3(0, 0, 0));
}

TEST(TrajectoryCsv, BomCaseAndColumnOrderAreAccepted) {
  const RecordedTrajectory t =
      read_trajectory_csv(write("bom.csv", "\xEF\xBB\xBFTime,QW,X,Y,Z,QX,QY,QZ,extra\r\n0,2,1,2,3,0,0,0,a\r\n"));
  ASSERT_EQ(t.samples().size(), 1u);
  EXPECT_EQ(t.pose_at(0.0).position, Vec3(1, 2, 3));
  EXPECT_NEAR(t.pose_at(0.0).orientation.w(), 1.0, 1e-15);  // normalized
}

TEST(TrajectoryCsv, ErrorsNameFileLineAndColumn) {
  const std::string h = "time,x,y,z,qx,qy,qz,qw\n";
  std::string m = error_of(write("back.csv", h + "0,0,0,0,0,0,0,1\n2,0,0,0,0,0,0,1\n1,0,0,0,0,0,0,1\n"));
  EXPECT_NE(m.find("back.csv:4: column 'time': time goes backwards"), std::string::npos) << m;
  m = error_of(write("two_poses.csv", h + "0,0,0,0,0,0,0,1\n0,1,0,0,0,0,0,1\n"));
  EXPECT_NE(m.find("two_poses.csv:3: column 'time': two different poses"), std::string::npos) << m;
  m = error_of(write("word.csv", h + "0,0,0,0,0,0,0,1\n1,0,abc,0,0,0,0,1\n"));
  EXPECT_NE(m.find("word.csv:3: column 'y': not a number ('abc')"), std::string::npos) << m;
  m = error_of(write("nan.csv", h + "0,0,0,nan,0,0,0,1\n"));
  EXPECT_NE(m.find("nan.csv:2: column 'z': not finite"), std::string::npos) << m;
  m = error_of(write("inf.csv", h + "inf,0,0,0,0,0,0,1\n"));
  EXPECT_NE(m.find("inf.csv:2: column 'time': not finite"), std::string::npos) << m;
  m = error_of(write("zero_q.csv", h + "0,0,0,0,0,0,0,0\n"));
  EXPECT_NE(m.find("zero_q.csv:2:"), std::string::npos) << m;
  m = error_of(write("no_z.csv", "time,x,y\n0,0,0\n"));
  EXPECT_NE(m.find("no_z.csv:1: column 'z': missing"), std::string::npos) << m;
  m = error_of(write("part_q.csv", "time,x,y,z,qw\n0,0,0,0,1\n"));
  EXPECT_NE(m.find("part_q.csv:1:"), std::string::npos) << m;
  m = error_of(write("fields.csv", h + "0,0,0\n"));
  EXPECT_NE(m.find("fields.csv:2: expected 8 fields, got 3"), std::string::npos) << m;
  EXPECT_NE(error_of(write("empty.csv", "")).find("empty.csv: empty file"), std::string::npos);
  EXPECT_NE(error_of(write("header_only.csv", h)).find("header_only.csv: empty file"), std::string::npos);
  EXPECT_NE(error_of(temp_dir() / "missing.csv").find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace rfidray::io
