// Frame-to-frame NEES of a pose covariance (pose_nees.h).
#include "iraf_vo/eval/pose_nees.h"

namespace iraf_vo {

namespace {

Eigen::Vector3d logRotation(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

}  // namespace

bool frameToFrameNees(const Trajectory& gt, const std::vector<CovariancePose>& poses, std::vector<FrameToFrameError>* out,
                      std::string* err, EvalResult* alignment) {
  out->clear();
  Trajectory est;
  for (const CovariancePose& p : poses) est.push_back(p.stamp, p.T_w_c);
  EvalParams ep;
  EvalResult res;
  if (!evaluateTrajectory(gt, est, ep, &res, err)) return false;
  if (alignment) *alignment = res;
  const Sim3 to_est = res.alignment.inverse();  // GT -> estimate frame (its scale)
  std::vector<long> gt_of(est.size(), -1);
  for (const auto& p : associate(gt.stamps, est.stamps, ep.max_dt)) gt_of[p.second] = static_cast<long>(p.first);
  for (size_t k = 1; k < poses.size(); ++k) {
    if (poses[k].map != poses[k - 1].map || gt_of[k] < 0 || gt_of[k - 1] < 0) continue;
    const Eigen::Isometry3d G0 = to_est.apply(gt.poses[gt_of[k - 1]]), G1 = to_est.apply(gt.poses[gt_of[k]]);
    const Eigen::Isometry3d& T0 = poses[k - 1].T_w_c;
    const Eigen::Isometry3d& T1 = poses[k].T_w_c;
    FrameToFrameError f;
    f.index = k;
    f.error.head<3>() = (T1.translation() - T0.translation()) - (G1.translation() - G0.translation());
    f.error.tail<3>() = logRotation((T1.rotation() * T0.rotation().transpose()) *
                                    (G1.rotation() * G0.rotation().transpose()).transpose());
    const Eigen::Matrix<double, 6, 6> C = poses[k].covariance + poses[k - 1].covariance;
    f.nees = f.error.dot(C.ldlt().solve(f.error));
    f.nees_position = f.error.head<3>().dot(C.topLeftCorner<3, 3>().ldlt().solve(f.error.head<3>()));
    f.nees_rotation = f.error.tail<3>().dot(C.bottomRightCorner<3, 3>().ldlt().solve(f.error.tail<3>()));
    out->push_back(f);
  }
  return true;
}

double meanNees(const std::vector<FrameToFrameError>& errors) {
  double s = 0.0;
  for (const FrameToFrameError& e : errors) s += e.nees;
  return errors.empty() ? 0.0 : s / errors.size();
}

}  // namespace iraf_vo
