// Kinematics against closed form: the paper's differential drive (eq. 6–8), the mast (Fig. 11), mounting
// offsets, moving tags.
#include <gtest/gtest.h>

#include <cmath>

#include "core/differential_drive.h"
#include "core/error.h"
#include "core/mast.h"
#include "core/units.h"
#include "core/waypoint_trajectory.h"

namespace rfidray {
namespace {

double yaw_of(const Quat& q) {
  const Vec3 x = q * Vec3::UnitX();
  return std::atan2(x.y(), x.x());
}

// Rounding of a few sin/cos and one division: 1e-12 m is far above double error at metre scale.
constexpr double kTol = 1e-12;

TEST(WheelKinematics, Eq7Eq8AndInverse) {
  const double r = 0.11, d = 0.5;
  const WheelSpeeds w{2.0, 5.0};
  EXPECT_NEAR(body_speed_m_s(w, r), 0.11 * 7.0 / 2.0, kTol);          // eq. 7
  EXPECT_NEAR(body_turn_rate_rad_s(w, r, d), 0.11 * 3.0 / 0.5, kTol);  // eq. 8
  const WheelSpeeds back = wheel_speeds_for(body_speed_m_s(w, r), body_turn_rate_rad_s(w, r, d), r, d);
  EXPECT_NEAR(back.left_rad_s, 2.0, kTol);
  EXPECT_NEAR(back.right_rad_s, 5.0, kTol);
}

TEST(DifferentialDrive, StraightRunMatchesClosedForm) {
  DifferentialDriveParams p;
  p.wheel_radius_m = 0.1;
  p.track_width_m = 0.4;
  p.drive_wheel_speed_rad_s = 3.5;  // v = r ω = 0.35 m/s (eq. 7)
  p.start_s = 2.0;
  const DifferentialDriveTrajectory robot({Vec3(-1, -10, 0), Vec3(-1, 8, 0)}, p);
  const double v = 0.35, length = 18.0;
  ASSERT_EQ(robot.segments().size(), 1u);  // starts facing the first leg: no initial turn
  EXPECT_NEAR(robot.end_time_s(), 2.0 + length / v, 1e-9);
  EXPECT_FALSE(robot.is_static());
  for (double t : {0.0, 2.0, 3.7, 20.0, 2.0 + length / v, 100.0}) {
    const double s = std::clamp((t - 2.0) * v, 0.0, length);
    const Pose pose = robot.pose_at(t);
    EXPECT_NEAR(pose.position.x(), -1.0, kTol) << t;
    EXPECT_NEAR(pose.position.y(), -10.0 + s, 1e-9) << t;
    EXPECT_NEAR(pose.position.z(), 0.0, kTol);
    EXPECT_NEAR(yaw_of(pose.orientation), kPi / 2, kTol) << t;
  }
}

TEST(DifferentialDrive, InPlaceTurnDurationFromWheelSpeeds) {
  // The paper's L path: north 18 m, a quarter turn clockwise (to face +X) in place, then east 4 m.
  DifferentialDriveParams p;
  p.wheel_radius_m = 0.1;
  p.track_width_m = 0.4;
  p.drive_wheel_speed_rad_s = 3.5;
  p.turn_wheel_speed_rad_s = 1.5;
  const DifferentialDriveTrajectory robot({Vec3(-1, -10, 0), Vec3(-1, 8, 0), Vec3(3, 8, 0)}, p);
  const double v = 0.35;
  const double omega = 2.0 * 0.1 * 1.5 / 0.4;  // eq. 8 with ω_R = −ω_L = 1.5 rad/s: 0.75 rad/s
  const double t_corner = 18.0 / v;
  const double t_turn = (kPi / 2) / omega;     // heading +π/2 → 0: a quarter turn clockwise
  ASSERT_EQ(robot.segments().size(), 3u);
  const auto& turn = robot.segments()[1];
  EXPECT_NEAR(turn.v_m_s, 0.0, kTol);
  EXPECT_NEAR(turn.omega_rad_s, -omega, kTol);
  EXPECT_NEAR(turn.wheels.left_rad_s, 1.5, kTol);
  EXPECT_NEAR(turn.wheels.right_rad_s, -1.5, kTol);
  EXPECT_NEAR(turn.t1_s - turn.t0_s, t_turn, 1e-12);
  EXPECT_NEAR(robot.end_time_s(), t_corner + t_turn + 4.0 / v, 1e-9);

  // During the turn the robot stays on the corner and its heading falls linearly.
  for (double f : {0.0, 0.25, 0.5, 0.9}) {
    const Pose pose = robot.pose_at(t_corner + f * t_turn);
    EXPECT_NEAR(pose.position.x(), -1.0, 1e-9);
    EXPECT_NEAR(pose.position.y(), 8.0, 1e-9);
    EXPECT_NEAR(yaw_of(pose.orientation), kPi / 2 - omega * f * t_turn, 1e-9) << f;
  }
  // After the turn it drives east.
  const double t = t_corner + t_turn + 2.0;
  const Pose pose = robot.pose_at(t);
  EXPECT_NEAR(pose.position.x(), -1.0 + 2.0 * v, 1e-9);
  EXPECT_NEAR(pose.position.y(), 8.0, 1e-9);
  EXPECT_NEAR(yaw_of(pose.orientation), 0.0, 1e-9);
  // At the end it rests on the last waypoint.
  const Pose end = robot.pose_at(1e6);
  EXPECT_NEAR(end.position.x(), 3.0, 1e-12);
  EXPECT_NEAR(end.position.y(), 8.0, 1e-12);
}

TEST(DifferentialDrive, InitialHeadingAddsATurnTheShortWay) {
  DifferentialDriveParams p;
  p.has_initial_heading = true;
  p.initial_heading_rad = kPi;  // facing −X while the first leg goes +Y
  const DifferentialDriveTrajectory robot({Vec3(0, 0, 0), Vec3(0, 1, 0)}, p);
  ASSERT_EQ(robot.segments().size(), 2u);
  // From π to π/2 the short way is −π/2 (clockwise).
  EXPECT_LT(robot.segments()[0].omega_rad_s, 0.0);
  const double omega = 2.0 * p.wheel_radius_m * p.turn_wheel_speed_rad_s / p.track_width_m;
  EXPECT_NEAR(robot.segments()[0].t1_s, (kPi / 2) / omega, 1e-12);
}

TEST(DifferentialDrive, ArcClosedFormMatchesNumericIntegration) {
  // integrate_unicycle is the exact solution of eq. 6; compare with a fine RK4 integration.
  const PlanarState s0{1.0, 2.0, 0.3};
  const double v = 0.4, w = 0.7, T = 3.0;
  const PlanarState exact = integrate_unicycle(s0, v, w, T);
  PlanarState s = s0;
  const int n = 20000;
  const double h = T / n;
  auto f = [&](const PlanarState& q) { return Vec3(v * std::cos(q.heading_rad), v * std::sin(q.heading_rad), w); };
  for (int i = 0; i < n; ++i) {
    auto add = [](const PlanarState& q, const Vec3& k, double dt) {
      return PlanarState{q.x_m + dt * k.x(), q.y_m + dt * k.y(), q.heading_rad + dt * k.z()};
    };
    const Vec3 k1 = f(s), k2 = f(add(s, k1, h / 2)), k3 = f(add(s, k2, h / 2)), k4 = f(add(s, k3, h));
    s = add(s, (k1 + 2 * k2 + 2 * k3 + k4) / 6.0, h);
  }
  EXPECT_NEAR(exact.x_m, s.x_m, 1e-10);
  EXPECT_NEAR(exact.y_m, s.y_m, 1e-10);
  EXPECT_NEAR(exact.heading_rad, s.heading_rad, 1e-12);
}

TEST(DifferentialDrive, RejectsBadParameters) {
  DifferentialDriveParams p;
  p.wheel_radius_m = 0.0;
  EXPECT_THROW(DifferentialDriveTrajectory({Vec3(0, 0, 0), Vec3(1, 0, 0)}, p), InputError);
  p = {};
  p.track_width_m = -1.0;
  EXPECT_THROW(DifferentialDriveTrajectory({Vec3(0, 0, 0), Vec3(1, 0, 0)}, p), InputError);
  p = {};
  EXPECT_THROW(DifferentialDriveTrajectory({Vec3(0, 0, 0), Vec3(NAN, 0, 0)}, p), InputError);
  EXPECT_THROW(DifferentialDriveTrajectory({}, p), InputError);
}

TEST(Mast, StaysWithinBoundsWithTrianglePeriod) {
  const MastParams p{0.5, 2.0, 0.25, 0.0};
  const double period = 2.0 * 1.5 / 0.25;  // 12 s
  EXPECT_NEAR(mast_period_s(p), period, kTol);
  EXPECT_NEAR(mast_height_m(p, 0.0), 0.5, kTol);
  EXPECT_NEAR(mast_height_m(p, period / 2), 2.0, kTol);
  EXPECT_NEAR(mast_height_m(p, 2.0), 0.5 + 0.25 * 2.0, kTol);         // going up
  EXPECT_NEAR(mast_height_m(p, period / 2 + 2.0), 2.0 - 0.5, kTol);   // coming down
  double lo = 1e9, hi = -1e9;
  for (int i = 0; i <= 4000; ++i) {
    const double t = i * 0.01;
    const double z = mast_height_m(p, t);
    lo = std::min(lo, z);
    hi = std::max(hi, z);
    EXPECT_NEAR(z, mast_height_m(p, t + period), 1e-9) << t;  // periodic
  }
  EXPECT_GE(lo, 0.5 - kTol);
  EXPECT_LE(hi, 2.0 + kTol);
  EXPECT_NEAR(lo, 0.5, 1e-9);
  EXPECT_NEAR(hi, 2.0, 1e-9);
  EXPECT_THROW(MastTrajectory(std::make_shared<StaticTrajectory>(Pose{}), MastParams{2.0, 1.0, 0.1, 0.0}),
               InputError);
  EXPECT_THROW(MastTrajectory(std::make_shared<StaticTrajectory>(Pose{}), MastParams{0.0, 1.0, 0.0, 0.0}),
               InputError);
}

TEST(Mounting, MastOnRobotWithOffsetComposes) {
  DifferentialDriveParams p;
  p.turn_wheel_speed_rad_s = 2.0;
  auto robot = std::make_shared<DifferentialDriveTrajectory>(std::vector<Vec3>{Vec3(0, 0, 0), Vec3(0, 5, 0)}, p);
  const MastParams mp{0.5, 1.5, 0.2, 0.0};
  auto mast = std::make_shared<MastTrajectory>(robot, mp);
  // Antenna 0.3 m to the robot's right (−y in the robot frame), facing right (yaw −90°).
  const Pose offset{Vec3(0.1, -0.3, 0.2), Quat(Eigen::AngleAxisd(-kPi / 2, Vec3::UnitZ()))};
  const MountedTrajectory antenna(mast, offset);
  const double t = 3.0;
  const double v = p.wheel_radius_m * p.drive_wheel_speed_rad_s;
  const Pose pose = antenna.pose_at(t);
  // Robot faces +Y (yaw π/2): robot x → world +Y, robot −y → world +X.
  EXPECT_NEAR(pose.position.x(), 0.3, 1e-12);
  EXPECT_NEAR(pose.position.y(), v * t + 0.1, 1e-12);
  EXPECT_NEAR(pose.position.z(), mast_height_m(mp, t) + 0.2, 1e-12);
  EXPECT_NEAR(yaw_of(pose.orientation), 0.0, 1e-12);  // π/2 − π/2: facing +X, the robot's right
  EXPECT_FALSE(antenna.is_static());
  EXPECT_EQ(antenna.end_time_s(), kNeverSettles);
}

TEST(WaypointTrajectory, ConstantSpeedAlongLegs) {
  const Quat q(Eigen::AngleAxisd(0.4, Vec3::UnitZ()));
  const WaypointTrajectory tag({Vec3(0, 0, 1), Vec3(3, 0, 1), Vec3(3, 4, 1)}, 0.5, q, 10.0);
  EXPECT_NEAR(tag.end_time_s(), 10.0 + 7.0 / 0.5, kTol);
  EXPECT_TRUE(tag.pose_at(5.0).position.isApprox(Vec3(0, 0, 1)));
  EXPECT_NEAR((tag.pose_at(12.0).position - Vec3(1, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((tag.pose_at(18.0).position - Vec3(3, 1, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((tag.pose_at(99.0).position - Vec3(3, 4, 1)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(tag.pose_at(12.0).orientation.isApprox(q));
  EXPECT_FALSE(tag.is_static());
  EXPECT_TRUE(WaypointTrajectory({Vec3(1, 2, 3)}, 0.0, Quat::Identity()).is_static());
  EXPECT_THROW(WaypointTrajectory({Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0.0, Quat::Identity()), InputError);
}

}  // namespace
}  // namespace rfidray
