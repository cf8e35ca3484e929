#include "iraf_vo/sim/sim_stereo_rig.h"

#include <cmath>
#include <sstream>

namespace iraf_vo {

double defaultStereoBaseline(const std::string& camera) {
  if (camera == "pinhole") return 0.110;   // EuRoC cam0-cam1
  if (camera == "fisheye") return 0.101;   // TUM-VI cam0-cam1
  if (camera == "kitti") return 0.54;      // KITTI odometry grayscale pair
  return 0.10;                             // davis240 and sensor.yaml cameras
}

std::string validate(const SimStereoRig& rig) {
  std::ostringstream err;
  if (!(rig.baseline_m <= 5.0)) err << "baseline must be <= 5 m (got " << rig.baseline_m << "); ";
  for (const double a : {rig.yaw_deg, rig.pitch_deg, rig.roll_deg})
    if (!(std::abs(a) <= 10.0)) {
      err << "rig angles must be within +-10 deg (got " << a << "); ";
      break;
    }
  return err.str();
}

Eigen::Isometry3d rightCameraInLeft(const SimStereoRig& rig, const std::string& camera) {
  const double deg = M_PI / 180.0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rig.yaw_deg * deg, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rig.pitch_deg * deg, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(rig.roll_deg * deg, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(rig.baseline_m > 0.0 ? rig.baseline_m : defaultStereoBaseline(camera), 0.0, 0.0);
  return T;
}

}  // namespace iraf_vo
