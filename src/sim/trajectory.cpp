#include "iraf_vo/sim/trajectory.h"

#include <cmath>
#include <sstream>

#include "iraf_vo/common/enum_names.h"

namespace iraf_vo {

namespace {

constexpr double kDeg = M_PI / 180.0;

/// Optical frame (x right, y down, z forward) of a body (x forward, y left, z up) with yaw, pitch, roll.
Eigen::Matrix3d opticalFromBody(double yaw, double pitch, double roll) {
  const Eigen::Matrix3d R_WB = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())).toRotationMatrix();
  // Optical frame in body: x_C = -y_B (right), y_C = -z_B (down), z_C = x_B (forward).
  Eigen::Matrix3d R_BC;
  R_BC << 0, 0, 1,
         -1, 0, 0,
          0, -1, 0;
  return R_WB * R_BC;
}

Eigen::Isometry3d makePose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

/// Room loop; `hand` adds the hand-held rotations (handheld_fast), driven by the motion clock t.
Eigen::Isometry3d loopPose(const TrajectoryParams& p, double t, bool hand) {
  const double th = p.start_phase + 2.0 * M_PI * p.speed * t / p.loop_period_s;
  // Position: ellipse with a radial wobble and a height variation.
  const double wobble = 0.08 * std::sin(3.0 * th + 0.4);
  const double x = (p.radius_x + wobble) * std::cos(th);
  const double y = (p.radius_y + wobble) * std::sin(th);
  const double z = p.height + p.height_amplitude * std::sin(2.0 * th + 0.3);
  // Body attitude (x forward, y left, z up): yaw follows the loop (travel direction th + 90 deg),
  // turned outwards, plus small oscillations.
  double yaw = th + M_PI / 2 - p.look_outward_deg * kDeg + p.yaw_amplitude_deg * kDeg * std::sin(3.0 * th + 1.0);
  double pitch = p.pitch_down_deg * kDeg + p.pitch_amplitude_deg * kDeg * std::sin(2.0 * th + 1.3);
  double roll = p.roll_amplitude_deg * kDeg * std::sin(1.5 * th + 0.2);
  if (hand) {
    const double w = 2.0 * M_PI * p.speed * t;
    yaw += p.hand_yaw_deg * kDeg * std::sin(p.hand_yaw_hz * w + 0.3);
    pitch += p.hand_pitch_deg * kDeg * std::sin(p.hand_pitch_hz * w + 1.1);
    roll += p.hand_roll_deg * kDeg * std::sin(p.hand_roll_hz * w + 2.0);
  }
  return makePose(opticalFromBody(yaw, pitch, roll), Eigen::Vector3d(x, y, z));
}

double driveHeading(const TrajectoryParams& p, double s) {
  return p.drive_turn_deg * kDeg * std::sin(2.0 * M_PI * s / p.drive_turn_period_m);
}

Eigen::Isometry3d drivePose(const TrajectoryParams& p, double t) {
  const double s = p.drive_speed_mps * t;
  double heading = 0.0;
  const Eigen::Vector2d c = drivePath(p, s, &heading);
  const Eigen::Vector2d left(-std::sin(heading), std::cos(heading));
  const Eigen::Vector2d xy = c + p.drive_lane_offset_m * left;
  // Suspension: small pitch/roll vibrations and a 1 cm height bounce (two incommensurate frequencies).
  const double a = p.drive_vibration_deg * kDeg;
  const double pitch = a * (0.6 * std::sin(2 * M_PI * 1.3 * t + 0.5) + 0.4 * std::sin(2 * M_PI * 3.1 * t + 1.7));
  const double roll = a * (0.6 * std::sin(2 * M_PI * 0.9 * t + 2.1) + 0.4 * std::sin(2 * M_PI * 2.3 * t + 0.2));
  const double z = p.drive_height_m + 0.01 * std::sin(2 * M_PI * 1.7 * t + 0.9);
  return makePose(opticalFromBody(heading, pitch, roll), Eigen::Vector3d(xy.x(), xy.y(), z));
}

Eigen::Isometry3d sliderPose(const TrajectoryParams& p, double t) {
  // Constant speed, back and forth (triangle wave) between -travel/2 and +travel/2, starting at -travel/2.
  const double L = p.slider_travel_m;
  const double u = std::fmod(p.slider_speed_mps * t, 2.0 * L);
  const double x = u <= L ? -L / 2 + u : L / 2 - (u - L);
  // Looking along +y (body yaw 90 deg), pitched down; the attitude never changes.
  return makePose(opticalFromBody(M_PI / 2, p.slider_pitch_down_deg * kDeg, 0.0),
                  Eigen::Vector3d(x, p.slider_y_m, p.slider_height_m));
}

}  // namespace

namespace {
constexpr EnumName<MotionKind> kMotionNames[] = {{MotionKind::kRoom, "room"},
                                                 {MotionKind::kDrive, "drive"},
                                                 {MotionKind::kSlider, "slider"},
                                                 {MotionKind::kHandheldFast, "handheld_fast"},
                                                 {MotionKind::kHighway, "highway"}};
}  // namespace

const char* toString(MotionKind m) { return nameOf(kMotionNames, m); }

bool parseMotionKind(const std::string& s, MotionKind* m) { return parseName(kMotionNames, s, m); }

std::string motionKindNames() { return "room|drive|slider|handheld_fast|highway"; }

std::string validate(const TrajectoryParams& p) {
  std::ostringstream err;
  if (!(p.static_start_s >= 0.0)) err << "static_start_s must be >= 0 (got " << p.static_start_s << "); ";
  if (!(p.start_ramp_s > 0.0)) err << "start_ramp_s must be > 0 (got " << p.start_ramp_s << "); ";
  if (!(p.loop_period_s > 0.0)) err << "loop_period_s must be > 0; ";
  if (!(p.drive_speed_mps >= 0.0)) err << "drive_speed_mps must be >= 0; ";
  if (!(p.drive_turn_period_m > 0.0)) err << "drive_turn_period_m must be > 0; ";
  if (!(p.slider_speed_mps >= 0.0)) err << "slider_speed_mps must be >= 0; ";
  if (!(p.slider_travel_m > 0.0)) err << "slider_travel_m must be > 0 (got " << p.slider_travel_m << "); ";
  return err.str();
}

double motionClock(const TrajectoryParams& p, double t) {
  if (!(p.static_start_s > 0.0)) return t;
  const double u = t - p.static_start_s;
  if (u <= 0.0) return 0.0;
  const double r = p.start_ramp_s;
  return u < r ? 0.5 * u * u / r : u - 0.5 * r;
}

Eigen::Vector2d drivePath(const TrajectoryParams& p, double s, double* heading) {
  // x(s) = int cos(psi), y(s) = int sin(psi) with psi(s) = A sin(2 pi s / P): Simpson's rule, <= 0.5 m steps.
  const int n = 2 * std::max(1, static_cast<int>(std::ceil(std::abs(s) / 1.0)));
  const double h = s / n;
  Eigen::Vector2d acc = Eigen::Vector2d::Zero();
  for (int i = 0; i <= n; ++i) {
    const double psi = driveHeading(p, i * h);
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    acc += w * Eigen::Vector2d(std::cos(psi), std::sin(psi));
  }
  if (heading) *heading = driveHeading(p, s);
  return acc * (h / 3.0);
}

Eigen::Isometry3d trajectoryPose(const TrajectoryParams& p, double t) {
  const double tm = motionClock(p, t);
  switch (p.motion) {
    case MotionKind::kDrive:
    case MotionKind::kHighway: return drivePose(p, tm);
    case MotionKind::kSlider: return sliderPose(p, tm);
    case MotionKind::kHandheldFast: return loopPose(p, tm, true);
    case MotionKind::kRoom: break;
  }
  return loopPose(p, tm, false);
}

}  // namespace iraf_vo
