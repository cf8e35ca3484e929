#include "iraf_vo/sim/trajectory.h"

#include <cmath>

namespace iraf_vo {

Eigen::Isometry3d trajectoryPose(const TrajectoryParams& p, double t) {
  const double deg = M_PI / 180.0;
  const double th = p.start_phase + 2.0 * M_PI * p.speed * t / p.loop_period_s;
  // Position: ellipse with a radial wobble and a height variation.
  const double wobble = 0.08 * std::sin(3.0 * th + 0.4);
  const double x = (p.radius_x + wobble) * std::cos(th);
  const double y = (p.radius_y + wobble) * std::sin(th);
  const double z = p.height + p.height_amplitude * std::sin(2.0 * th + 0.3);
  // Body attitude (x forward, y left, z up): yaw follows the loop (travel direction th + 90 deg),
  // turned outwards, plus small oscillations.
  const double yaw = th + M_PI / 2 - p.look_outward_deg * deg + p.yaw_amplitude_deg * deg * std::sin(3.0 * th + 1.0);
  const double pitch = p.pitch_down_deg * deg + p.pitch_amplitude_deg * deg * std::sin(2.0 * th + 1.3);
  const double roll = p.roll_amplitude_deg * deg * std::sin(1.5 * th + 0.2);
  const Eigen::Matrix3d R_WB = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())).toRotationMatrix();
  // Optical frame in body: x_C = -y_B (right), y_C = -z_B (down), z_C = x_B (forward).
  Eigen::Matrix3d R_BC;
  R_BC << 0, 0, 1,
         -1, 0, 0,
          0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_WB * R_BC;
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

}  // namespace iraf_vo
