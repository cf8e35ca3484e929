// iraf_vo_pose_nees --dataset DIR [--camera sensor.yaml] [--config yaml] [--frames N] [--gt FILE] [--csv FILE]
// How well the tracker's pose covariance (TrackResult::covariance, published in odometry.pose.covariance) predicts
// its frame-to-frame error: for consecutive TRACKING frames of one map, the error of the relative motion (camera
// centre step and world-frame rotation step, after the Sim(3) alignment of the whole run to the ground truth)
// against C_k + C_k-1:  NEES = e^T (C_k + C_k-1)^-1 e. A consistent covariance gives a mean NEES near the degrees of
// freedom (6; 3 for position, 3 for rotation); larger = optimistic. Prints the mean / median and the factor that
// would make the mean equal to the degrees of freedom. Ground truth: DIR/groundtruth.txt (iraf_vo_simulate).
// --csv: one row per frame pair for fitting a calibration: stamp, e (6); for frame k-1 then k: median chi2,
// inliers, used_pnp, C (36, row-major); for frame k-1 then k: the deviation from the constant-velocity
// extrapolation of the two output poses before it (6, zero without both); |step| of the centre, |step| of the
// rotation, keyframe flags of k-1 and k.
#include <iraf_vo/camera/camera_loader.h>
#include <iraf_vo/eval/pose_nees.h>
#include <iraf_vo/io/image_folder.h>
#include <iraf_vo/pipeline/frame_source.h>
#include <iraf_vo/pipeline/offline_pipeline.h>
#include <iraf_vo/pipeline/pipeline_params.h>
#include <iraf_vo/tracking/tracker.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Sample {
  double stamp;
  Eigen::Isometry3d T;
  Eigen::Matrix<double, 6, 6> C;
  long map;
  double median_chi2;
  int inliers;
  bool used_pnp;
  bool keyframe;
};

Eigen::Vector3d logRotation(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/// One row per frame pair (see the header comment).
bool writeCsv(const std::string& path, const std::vector<Sample>& samples,
              const std::vector<iraf_vo::FrameToFrameError>& errors) {
  FILE* csv = std::fopen(path.c_str(), "w");
  if (!csv) return false;
  for (const iraf_vo::FrameToFrameError& f : errors) {
    const size_t k = f.index;
    std::fprintf(csv, "%.6f", samples[k].stamp);
    for (int i = 0; i < 6; ++i) std::fprintf(csv, ",%.9g", f.error[i]);
    for (size_t j : {k - 1, k}) {
      std::fprintf(csv, ",%.6g,%d,%d", samples[j].median_chi2, samples[j].inliers, int(samples[j].used_pnp));
      for (int i = 0; i < 36; ++i) std::fprintf(csv, ",%.9g", samples[j].C(i / 6, i % 6));
    }
    for (size_t j : {k - 1, k}) {
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      if (j >= 2 && samples[j - 2].map == samples[j].map) {
        const Eigen::Isometry3d vel = samples[j - 1].T.inverse() * samples[j - 2].T;  // T_cw[j-1] T_cw[j-2]^-1
        const Eigen::Isometry3d pred = (vel * samples[j - 1].T.inverse()).inverse();
        d.head<3>() = samples[j].T.translation() - pred.translation();
        d.tail<3>() = logRotation(samples[j].T.rotation() * pred.rotation().transpose());
      }
      for (int i = 0; i < 6; ++i) std::fprintf(csv, ",%.9g", d[i]);
    }
    const Eigen::Vector3d step = samples[k].T.translation() - samples[k - 1].T.translation();
    std::fprintf(csv, ",%.9g,%.9g,%d,%d\n", step.norm(),
                 logRotation(samples[k].T.rotation() * samples[k - 1].T.rotation().transpose()).norm(),
                 int(samples[k - 1].keyframe), int(samples[k].keyframe));
  }
  return std::fclose(csv) == 0;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string dataset, camera_path, config, gt_path, csv_path;
  long frames = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--dataset") dataset = value();
    else if (a == "--camera") camera_path = value();
    else if (a == "--config") config = value();
    else if (a == "--gt") gt_path = value();
    else if (a == "--csv") csv_path = value();
    else if (a == "--frames") frames = std::atol(value().c_str());
    else return std::fprintf(stderr, "usage: iraf_vo_pose_nees --dataset DIR [--camera Y] [--config Y] [--frames N] [--gt F] [--csv F]\n"), 2;
  }
  iraf_vo::AslImageReader asl;
  std::string err;
  if (dataset.empty() || !asl.open(dataset, &err)) return std::fprintf(stderr, "iraf_vo_pose_nees: --dataset: %s\n", err.c_str()), 1;
  if (camera_path.empty()) camera_path = asl.sensorYamlPath();
  if (gt_path.empty()) gt_path = dataset + "/groundtruth.txt";
  const iraf_vo::CameraModelPtr cam = iraf_vo::loadCamera(camera_path, &err);
  if (!cam) return std::fprintf(stderr, "iraf_vo_pose_nees: --camera %s: %s\n", camera_path.c_str(), err.c_str()), 1;
  iraf_vo::PipelineParams params;
  if (!config.empty() && !iraf_vo::loadPipelineConfig(config, &params, &err))
    return std::fprintf(stderr, "iraf_vo_pose_nees: %s\n", err.c_str()), 1;
  iraf_vo::applyResolutionRule(*cam, &params);
  params.tracker.mapping_thread = false;  // deterministic
  iraf_vo::Trajectory gt;
  if (!iraf_vo::readTrajectory(gt_path, &gt, &err, cam->T_BS))
    return std::fprintf(stderr, "iraf_vo_pose_nees: --gt %s: %s\n", gt_path.c_str(), err.c_str()), 1;

  iraf_vo::AslFrameSource source(&asl);
  iraf_vo::PipelineOptions opts;
  opts.last = frames > 0 ? std::min<long>(frames, source.size()) : static_cast<long>(source.size());
  opts.width = cam->width();
  opts.height = cam->height();
  iraf_vo::Tracker tracker(cam, params.tracker);
  std::vector<Sample> samples;
  long map = 0;
  {
    iraf_vo::OfflinePipeline pipeline(&source, params.enhance, params.features, opts);
    for (iraf_vo::FrontEndItem it; pipeline.next(&it);) {
      if (it.fatal) return std::fprintf(stderr, "iraf_vo_pose_nees: %s\n", it.message.c_str()), 1;
      if (it.error) continue;
      const iraf_vo::TrackResult r = tracker.track(it.frame);
      if (r.initialized_now) ++map;
      if (r.state != iraf_vo::TrackingState::kTracking) continue;
      samples.push_back({it.frame.stamp, r.T_w_c, r.covariance, map, r.median_chi2, r.inliers, r.used_pnp, r.is_keyframe});
    }
  }
  std::vector<iraf_vo::CovariancePose> poses;
  for (const Sample& x : samples) poses.push_back({x.stamp, x.T, x.C, x.map});
  std::vector<iraf_vo::FrameToFrameError> errors;
  iraf_vo::EvalResult res;
  if (!iraf_vo::frameToFrameNees(gt, poses, &errors, &err, &res))
    return std::fprintf(stderr, "iraf_vo_pose_nees: %s\n", err.c_str()), 1;
  std::vector<double> nees6, nees_t, nees_r;
  for (const iraf_vo::FrameToFrameError& f : errors) {
    nees6.push_back(f.nees);
    nees_t.push_back(f.nees_position);
    nees_r.push_back(f.nees_rotation);
  }
  if (!csv_path.empty() && !writeCsv(csv_path, samples, errors))
    return std::fprintf(stderr, "iraf_vo_pose_nees: --csv %s: cannot write\n", csv_path.c_str()), 1;
  std::printf("%s: %zu tracked, %zu frame pairs, ATE %.4f (scale %.3f)\n", dataset.c_str(), samples.size(),
              nees6.size(), res.ate.rmse, res.scale);
  std::printf("NEES 6-dof mean %.2f median %.2f (dof 6) -> factor %.2f\n", mean(nees6), median(nees6), mean(nees6) / 6.0);
  std::vector<double> chi2;
  for (const Sample& x : samples) chi2.push_back(x.median_chi2);
  std::printf("median chi2 of the inliers: median %.2f mean %.2f\n", median(chi2), mean(chi2));
  std::printf("NEES position mean %.2f median %.2f (dof 3) -> factor %.2f\n", mean(nees_t), median(nees_t), mean(nees_t) / 3.0);
  std::printf("NEES rotation mean %.2f median %.2f (dof 3) -> factor %.2f\n", mean(nees_r), median(nees_r), mean(nees_r) / 3.0);
  return 0;
}
