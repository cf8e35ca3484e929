// Two-view initialization (two_view.h): ORB-SLAM model selection between E and H (fitted and scored in
// two_view_models.h), decomposition into (R, t) hypotheses checked by triangulation, and a two-view BA. ROS-free.
#include "iraf_vo/tracking/two_view.h"

#include "iraf_vo/tracking/bundle_adjustment.h"
#include "iraf_vo/tracking/geometry.h"
#include "iraf_vo/tracking/multiview.h"
#include "iraf_vo/tracking/two_view_ambiguity.h"
#include "iraf_vo/tracking/two_view_models.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

namespace iraf_vo {

namespace {

// Pinhole without distortion on normalized coordinates scaled by `focal` (principal point 0): lets the two-view
// refinement reuse bundleAdjust() on bearings with pixel-like residuals.
class NormalizedPinhole final : public CameraModel {
 public:
  explicit NormalizedPinhole(double f) : f_(f) {}
  std::string modelName() const override { return "normalized"; }
  CameraKind kind() const override { return CameraKind::kPinhole; }
  std::string distortionModel() const override { return "none"; }
  bool project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J) const override {
    if (p.z() <= 1e-9) return false;
    const double iz = 1.0 / p.z();
    *uv = Eigen::Vector2d(f_ * p.x() * iz, f_ * p.y() * iz);
    if (J) *J << f_ * iz, 0, -f_ * p.x() * iz * iz, 0, f_ * iz, -f_ * p.y() * iz * iz;
    return true;
  }
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* b) const override {
    *b = Eigen::Vector3d(uv.x() / f_, uv.y() / f_, 1.0).normalized();
    return true;
  }
  std::vector<double> parameters() const override { return {f_, f_, 0, 0}; }
  double focal() const override { return f_; }

 private:
  double f_;
};

struct Hypothesis {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  int good = 0;
  double parallax_deg = 0.0;         // the tested one (TwoViewParams::min_parallax_points)
  double median_parallax_deg = 0.0;
  double few_parallax_deg = 0.0;     // the determined_parallax_points-th largest
  std::vector<Eigen::Vector3d> points;
  std::vector<char> ok;
};

// Triangulate the inliers with (R, t): cheirality, reprojection (pixels via focal) and parallax checks.
// parallax_deg = the min_parallax_points-th largest parallax (ORB-SLAM CheckRT: the 50th), 0: the median.
void checkRT(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const std::vector<Eigen::Vector3d>& b1,
             const std::vector<Eigen::Vector3d>& b2, const std::vector<char>& inl, double focal,
             const TwoViewParams& params, Hypothesis* h) {
  h->R = R;
  h->t = t;
  h->good = 0;
  h->points.assign(b1.size(), Eigen::Vector3d::Zero());
  h->ok.assign(b1.size(), 0);
  Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity(), T2 = Eigen::Isometry3d::Identity();
  T2.linear() = R;
  T2.translation() = t;
  const double th2 = params.threshold_px * params.threshold_px * 4.0;  // chi2-like gate: (2 sigma)^2
  std::vector<double> parallaxes;
  for (size_t i = 0; i < b1.size(); ++i) {
    if (!inl[i]) continue;
    Eigen::Vector3d X;
    if (!triangulateBearings(T1, b1[i], T2, b2[i], &X) || !X.allFinite()) continue;
    const Eigen::Vector3d X2 = R * X + t;
    if (X.z() <= 0 || X2.z() <= 0) continue;
    // angular reprojection error converted to pixels
    const double e1 = (X.normalized() - b1[i].normalized()).squaredNorm() * focal * focal;
    const double e2 = (X2.normalized() - b2[i].normalized()).squaredNorm() * focal * focal;
    if (e1 > th2 || e2 > th2) continue;
    const double cosp = X.normalized().dot((X + R.transpose() * t).normalized());  // rays from both centres
    h->points[i] = X;
    h->ok[i] = 1;
    ++h->good;
    parallaxes.push_back(std::acos(std::clamp(cosp, -1.0, 1.0)) * 180.0 / M_PI);
  }
  if (!parallaxes.empty()) {
    std::sort(parallaxes.begin(), parallaxes.end(), std::greater<double>());
    h->median_parallax_deg = parallaxes[parallaxes.size() / 2];
    const size_t n = parallaxes.size();
    const size_t rank = params.min_parallax_points > 0 ? std::min<size_t>(params.min_parallax_points, n) - 1 : n / 2;
    h->parallax_deg = parallaxes[rank];
    if (params.determined_parallax_points > 0)
      h->few_parallax_deg = parallaxes[std::min<size_t>(params.determined_parallax_points, n) - 1];
  }
}


// Every (R, t) the chosen model decomposes into, each triangulated and checked (checkRT).
std::vector<Hypothesis> poseHypotheses(const TwoViewModels& models, bool use_h, const ForwardMatches& m, double focal,
                                       const TwoViewParams& params) {
  std::vector<Hypothesis> hyps;
  if (use_h) {
    std::vector<cv::Mat> Rs, ts, ns;
    cv::decomposeHomographyMat(models.H, cv::Mat::eye(3, 3, CV_64F), Rs, ts, ns);
    for (size_t k = 0; k < Rs.size(); ++k) {
      Eigen::Matrix3d R;
      Eigen::Vector3d t;
      cv::cv2eigen(Rs[k], R);
      cv::cv2eigen(ts[k], t);
      if (t.norm() < 1e-9) continue;
      hyps.emplace_back();
      checkRT(R, t.normalized(), m.b1, m.b2, models.inliers_h, focal, params, &hyps.back());
    }
  } else {
    cv::Mat R1, R2, t;
    cv::decomposeEssentialMat(models.E, R1, R2, t);
    Eigen::Matrix3d Ra, Rb;
    Eigen::Vector3d te;
    cv::cv2eigen(R1, Ra);
    cv::cv2eigen(R2, Rb);
    cv::cv2eigen(t, te);
    for (const auto& R : {Ra, Rb})
      for (double s : {1.0, -1.0}) {
        hyps.emplace_back();
        checkRT(R, s * te.normalized(), m.b1, m.b2, models.inliers_e, focal, params, &hyps.back());
      }
  }
  return hyps;
}

// The hypothesis with the most good points, if it is unambiguous, triangulates enough and has enough parallax
// (allow_few: an essential-matrix motion may pass with determined_parallax_points, see TwoViewParams).
const Hypothesis* selectHypothesis(std::vector<Hypothesis>* hyps, const TwoViewParams& params, bool allow_few,
                                   TwoViewResult* res) {
  if (hyps->empty()) {
    res->reason = res->model + ": no decomposition";
    return nullptr;
  }
  std::sort(hyps->begin(), hyps->end(), [](const Hypothesis& a, const Hypothesis& b) { return a.good > b.good; });
  const Hypothesis& best = (*hyps)[0];
  const int second = hyps->size() > 1 ? (*hyps)[1].good : 0;
  res->median_parallax_deg = best.median_parallax_deg;
  res->parallax_deg = best.parallax_deg;
  res->num_triangulated = best.good;
  if (best.good < params.min_triangulated) {
    res->reason = res->model + ": too few triangulated points (" + std::to_string(best.good) + ")";
    return nullptr;
  }
  if (second > 0.75 * best.good) {
    res->reason = res->model + ": ambiguous decomposition (" + std::to_string(best.good) + " vs " +
                  std::to_string(second) + ")";
    return nullptr;
  }
  // A homography fitted to a non-planar scene with little parallax decomposes into a wrong motion with spurious
  // parallax (measured: 0.95 deg median where the essential matrix gives 0.2): its median point must pass.
  const bool homography = res->model == "homography";
  const double tested = homography ? best.median_parallax_deg : best.parallax_deg;
  const bool strict = tested >= params.min_parallax_deg &&
                      best.median_parallax_deg >= (homography ? params.min_parallax_deg : params.min_median_parallax_deg);
  // Forward motion past far structure: only the few near points have parallax. Accepted when the translation is
  // determined (the ambiguity check, run after the refinement, refuses it otherwise).
  res->few_parallax_points = allow_few && !strict && !homography && params.determined_parallax_points > 0 &&
                             params.ambiguity_max_chi2 > 0.0 && best.few_parallax_deg >= params.min_parallax_deg;
  if (res->few_parallax_points) res->parallax_deg = best.few_parallax_deg;
  if (!strict && !res->few_parallax_points) {
    res->reason = res->model + ": parallax too low (" + std::to_string(best.parallax_deg) + " deg; median " +
                  std::to_string(best.median_parallax_deg) + ")";
    return nullptr;
  }
  return &best;
}

// Whether a homography hypothesis's motion explains the matches the essential matrix holds off the plane (its
// inliers that are not the homography's): most of them, as the true decomposition of a plane in a scene with
// depth does. The other decomposition of the pair maps the plane just as well but puts the camera on another path
// (on a road: moving vertically or sideways instead of forward, with a spurious parallax that passes the checks).
bool explainsOffPlaneMatches(const Hypothesis& h, const TwoViewModels& models, const ForwardMatches& m, double focal,
                             double threshold_px) {
  std::vector<char> inl;
  scoreEssential(skew(h.t) * h.R, m.p1, m.p2, focal, threshold_px, &inl);
  int off_plane = 0, explained = 0;
  for (size_t i = 0; i < inl.size(); ++i) {
    if (!models.inliers_e[i] || models.inliers_h[i]) continue;
    ++off_plane;
    explained += inl[i];
  }
  return 2 * explained >= off_plane;
}

// Gold-standard refinement: two-view BA on the triangulated inliers (frame 1 fixed; the scale gauge is fixed
// afterwards by normalizing |t| = 1). Writes R_21, t_21 and the points that pass cheirality and chi2.
void refineTwoView(const Hypothesis& best, const ForwardMatches& m, double focal, const TwoViewParams& params,
                   TwoViewResult* res) {
  NormalizedPinhole ncam(focal);
  std::vector<BAKeyframe> kf(2);
  kf[0].fixed = true;
  kf[1].T_c_w.linear() = best.R;
  kf[1].T_c_w.translation() = best.t;
  std::vector<BAPoint> bp;
  std::vector<BAObservation> bo;
  std::vector<int> which;
  for (size_t k = 0; k < m.index.size(); ++k) {
    if (!best.ok[k]) continue;
    const int pi = static_cast<int>(bp.size());
    bp.push_back({best.points[k]});
    bo.push_back({0, pi, focal * m.p1[k], params.threshold_px});
    bo.push_back({1, pi, focal * m.p2[k], params.threshold_px});
    which.push_back(static_cast<int>(k));
  }
  BAOptions bao;
  bao.max_num_iterations = 15;
  bao.max_cpu_seconds = 0.2;  // CPU time: the result does not depend on the machine load
  bao.max_solver_time_in_seconds = 4.0;  // wall-clock safety cap only
  bao.huber_delta = 1.0;
  bao.use_ceres = params.ba_use_ceres;
  BASummary bs;
  Eigen::Matrix3d R = best.R;
  Eigen::Vector3d t = best.t;
  double scale = 1.0;
  if (bundleAdjust(ncam, &kf, &bp, bo, bao, &bs) && kf[1].T_c_w.translation().norm() > 1e-9) {
    R = kf[1].T_c_w.rotation();
    scale = 1.0 / kf[1].T_c_w.translation().norm();
    t = kf[1].T_c_w.translation() * scale;
  } else {
    bs.outlier.assign(bo.size(), 0);
    for (size_t i = 0; i < bp.size(); ++i) bp[i].p_w = best.points[which[i]];
  }
  res->ok = true;
  res->R_21 = R;
  res->t_21 = t;
  int n = 0;
  for (size_t i = 0; i < which.size(); ++i) {
    if (bs.outlier[2 * i] || bs.outlier[2 * i + 1]) continue;
    const Eigen::Vector3d X = bp[i].p_w * scale;
    if (X.z() <= 0 || (R * X + t).z() <= 0) continue;
    res->points[m.index[which[i]]] = X;
    res->triangulated[m.index[which[i]]] = 1;
    ++n;
  }
  res->num_triangulated = n;
  if (n < params.min_triangulated) {
    res->ok = false;
    res->reason = res->model + ": too few points after refinement (" + std::to_string(n) + ")";
  }
}

// A planar scene leaves E undetermined (any translation fits), so only essential-matrix motions and homographies
// tried after the essential matrix scored higher (a scene with depth) are checked.
void checkTranslationAmbiguity(const ForwardMatches& m, double focal, const TwoViewParams& params,
                               TwoViewResult* res) {
  MotionAmbiguityParams ap;
  ap.sigma_px = params.threshold_px;
  ap.min_angle_deg = params.ambiguity_angle_deg;
  ap.max_delta_chi2 = params.ambiguity_max_chi2;
  const MotionAmbiguity a = findTranslationAmbiguity(m.p1, m.p2, res->R_21, res->t_21, focal, ap);
  res->translation_profile_chi2 = a.profile_chi2;
  if (!a.ambiguous && !(res->few_parallax_points && a.profile_chi2 < params.determined_min_chi2)) return;
  res->ok = false;
  if (!a.ambiguous) {
    char few[160];
    std::snprintf(few, sizeof(few),
                  "%s: parallax too low (%d-th point %.2f deg) for a translation this weakly determined (profile chi2 "
                  "%.1f < %.0f)",
                  res->model.c_str(), params.determined_parallax_points, res->parallax_deg, a.profile_chi2,
                  params.determined_min_chi2);
    res->reason = few;
    return;
  }
  char buf[160];
  if (a.refined_shift_deg >= ap.min_angle_deg)
    std::snprintf(buf, sizeof(buf), "%s: translation not determined (refined on all matches it moves %.0f deg)",
                  res->model.c_str(), a.refined_shift_deg);
  else
    std::snprintf(buf, sizeof(buf),
                  "%s: translation not determined (a direction %.0f deg away: profile chi2 %.1f < %.2f)",
                  res->model.c_str(), a.angle_deg, a.profile_chi2, params.ambiguity_max_chi2);
  res->reason = buf;
}

}  // namespace

TwoViewResult initializeTwoView(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                                double focal, const TwoViewParams& params) {
  TwoViewResult res;
  res.points.assign(b1.size(), Eigen::Vector3d::Zero());
  res.triangulated.assign(b1.size(), 0);
  if (b2.size() != b1.size()) {
    res.reason = "bearing vectors of different sizes";
    return res;
  }
  const ForwardMatches m = collectForwardMatches(b1, b2);
  if (m.index.size() < static_cast<size_t>(std::max(8, params.min_triangulated))) {
    res.reason = "too few matches (" + std::to_string(m.index.size()) + ")";
    return res;
  }
  const TwoViewModels models = fitEssentialAndHomography(m, focal, params, &res);
  if (!models.have_e && !models.have_h) {
    res.reason = "no essential / homography model";
    return res;
  }
  // Model selection, ORB-SLAM: R_H = S_H / (S_H + S_F).
  const double rh = res.score_h / std::max(1e-9, res.score_h + res.score_f);
  const bool use_h = models.have_h && (!models.have_e || rh > params.homography_ratio);
  res.model = use_h ? "homography" : "essential";
  std::vector<Hypothesis> hyps = poseHypotheses(models, use_h, m, focal, params);
  const Hypothesis* best = selectHypothesis(&hyps, params, false, &res);
  // Both models explain the matches about equally (small motion: R_H ~ 0.5) and the chosen one fails (e.g. an
  // ambiguous homography decomposition): the other model gets the same checks.
  std::vector<Hypothesis> other_hyps;
  const bool have_other = use_h ? models.have_e : models.have_h;
  if (!best && have_other && std::abs(rh - params.homography_ratio) < params.model_fallback_margin) {
    TwoViewResult other = res;
    other.model = use_h ? "essential" : "homography";
    other_hyps = poseHypotheses(models, !use_h, m, focal, params);
    best = selectHypothesis(&other_hyps, params, false, &other);
    // The essential matrix scored higher (R_H below the ratio): the scene has depth off the homography's plane,
    // and a decomposition that contradicts it is the wrong one of its pair.
    if (best && !use_h && !explainsOffPlaneMatches(*best, models, m, focal, params.threshold_px)) {
      other.reason = "homography: its motion contradicts the essential matrix's off-plane inliers";
      best = nullptr;
    }
    if (best) {
      res = other;
    } else {
      res.reason += "; " + other.reason;
    }
  }
  // Neither model passes the strict parallax test: the essential matrix's motion with few parallax-rich points
  // (forward driving past far structure), if its translation turns out determined.
  if (!best && models.have_e && params.determined_parallax_points > 0 && params.ambiguity_max_chi2 > 0.0) {
    std::vector<Hypothesis>* e_hyps = !use_h ? &hyps : &other_hyps;
    if (use_h && other_hyps.empty()) other_hyps = poseHypotheses(models, false, m, focal, params);
    TwoViewResult few = res;
    few.model = "essential";
    best = selectHypothesis(e_hyps, params, true, &few);
    if (best) res = few;
  }
  if (best && params.max_rotation_inlier_ratio < 1.0) {
    const std::vector<char>& inl = res.model == "homography" ? models.inliers_h : models.inliers_e;
    const int n_model = static_cast<int>(std::count(inl.begin(), inl.end(), 1));
    const int n_rot = inliersOfPureRotation(m.b1, m.b2, inl, focal, params.threshold_px);
    if (n_rot >= params.max_rotation_inlier_ratio * n_model) {
      res.reason = res.model + ": no translation (a pure rotation explains " + std::to_string(n_rot) + " of its " +
                   std::to_string(n_model) + " inliers)";
      best = nullptr;
    }
  }
  if (best) refineTwoView(*best, m, focal, params, &res);
  const bool fallback_homography = !use_h && res.model == "homography";
  if (res.ok && params.ambiguity_max_chi2 > 0.0 &&
      (res.model == "essential" || (fallback_homography && params.check_fallback_homography)))
    checkTranslationAmbiguity(m, focal, params, &res);
  if (!res.ok) {
    char buf[96];
    std::snprintf(buf, sizeof(buf), " [R_H %.2f; inliers E %d H %d]", rh,
                  static_cast<int>(std::count(models.inliers_e.begin(), models.inliers_e.end(), 1)),
                  static_cast<int>(std::count(models.inliers_h.begin(), models.inliers_h.end(), 1)));
    res.reason += buf;
  }
  return res;
}

}  // namespace iraf_vo
