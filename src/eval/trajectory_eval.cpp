#include "iraf_vo/eval/trajectory_eval.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "iraf_vo/common/enum_names.h"

namespace iraf_vo {

namespace {
constexpr EnumName<AlignMode> kAlignNames[] = {
    {AlignMode::kNone, "none"}, {AlignMode::kSE3, "se3"}, {AlignMode::kSim3, "sim3"}};
}  // namespace

bool parseAlignMode(const std::string& s_in, AlignMode* mode) {
  std::string s = s_in;
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return parseName(kAlignNames, s, mode);
}

const char* alignModeName(AlignMode m) { return nameOf(kAlignNames, m); }

Eigen::Isometry3d Sim3::apply(const Eigen::Isometry3d& T) const {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = R * T.linear();
  out.translation() = s * R * T.translation() + t;
  return out;
}

Sim3 Sim3::inverse() const {
  Sim3 inv;
  inv.s = 1.0 / s;
  inv.R = R.transpose();
  inv.t = -inv.s * (inv.R * t);
  return inv;
}

Eigen::Matrix4d Sim3::matrix() const {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = s * R;
  M.topRightCorner<3, 1>() = t;
  return M;
}

std::vector<std::pair<size_t, size_t>> associate(const std::vector<double>& t_gt, const std::vector<double>& t_est,
                                                 double max_dt) {
  struct Cand {
    double dt;
    size_t g, e;
  };
  std::vector<Cand> cands;
  for (size_t e = 0; e < t_est.size(); ++e) {
    auto lo = std::lower_bound(t_gt.begin(), t_gt.end(), t_est[e] - max_dt);
    for (auto it = lo; it != t_gt.end() && *it <= t_est[e] + max_dt; ++it) {
      cands.push_back({std::abs(*it - t_est[e]), static_cast<size_t>(it - t_gt.begin()), e});
    }
  }
  std::stable_sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) { return a.dt < b.dt; });
  std::vector<char> used_g(t_gt.size(), 0), used_e(t_est.size(), 0);
  std::vector<std::pair<size_t, size_t>> out;
  for (const Cand& c : cands) {
    if (used_g[c.g] || used_e[c.e]) continue;
    used_g[c.g] = used_e[c.e] = 1;
    out.emplace_back(c.g, c.e);
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool alignUmeyama(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt, AlignMode mode,
                  Sim3* S, std::string* error) {
  *S = Sim3();
  if (est.size() != gt.size()) {
    if (error) *error = "alignment: " + std::to_string(est.size()) + " estimate vs " + std::to_string(gt.size()) + " GT points";
    return false;
  }
  if (mode == AlignMode::kNone) {
    if (est.empty() && error) *error = "alignment: no matched poses";
    return !est.empty();
  }
  if (est.size() < 3) {
    if (error) *error = "alignment: " + std::to_string(est.size()) + " matched poses, need at least 3 for " + alignModeName(mode);
    return false;
  }
  Eigen::Matrix3Xd src(3, est.size()), dst(3, gt.size());
  for (size_t i = 0; i < est.size(); ++i) {
    src.col(i) = est[i];
    dst.col(i) = gt[i];
  }
  const double var_src = (src.colwise() - src.rowwise().mean()).squaredNorm() / est.size();
  const double var_dst = (dst.colwise() - dst.rowwise().mean()).squaredNorm() / gt.size();
  if (!(var_src > 1e-20) || !(var_dst > 1e-20)) {
    if (error) *error = "alignment: degenerate trajectory (all matched positions identical; estimate variance " +
                        std::to_string(var_src) + ", GT variance " + std::to_string(var_dst) + ")";
    return false;
  }
  // Umeyama, "Least-squares estimation of transformation parameters between two point patterns" (1991).
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, mode == AlignMode::kSim3);
  if (!T.allFinite()) {
    if (error) *error = "alignment: Umeyama returned a non-finite transform";
    return false;
  }
  const Eigen::Matrix3d sR = T.topLeftCorner<3, 3>();
  S->s = mode == AlignMode::kSim3 ? std::cbrt(sR.determinant()) : 1.0;
  S->R = sR / S->s;
  S->t = T.topRightCorner<3, 1>();
  return true;
}

ErrorStats computeStats(const std::vector<double>& e) {
  ErrorStats s;
  s.n = e.size();
  if (e.empty()) return s;
  double sum = 0, sq = 0;
  s.min = e[0];
  s.max = e[0];
  for (double v : e) {
    sum += v;
    sq += v * v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  s.mean = sum / e.size();
  s.rmse = std::sqrt(sq / e.size());
  s.std = std::sqrt(std::max(0.0, sq / e.size() - s.mean * s.mean));  // population std, as evo/numpy
  std::vector<double> sorted = e;
  std::sort(sorted.begin(), sorted.end());
  const size_t m = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  return s;
}

namespace {
/// RMSE of |gt_i - S(est_i)|.
double alignedRmse(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt, const Sim3& S) {
  double sum = 0.0;
  for (size_t i = 0; i < est.size(); ++i) sum += (S.apply(est[i]) - gt[i]).squaredNorm();
  return est.empty() ? 0.0 : std::sqrt(sum / est.size());
}

/// SE(3)-aligned ATE and the Sim(3) scale of the matched positions (left invalid when either alignment fails).
void measureMetricScale(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt,
                        EvalResult* r) {
  Sim3 se3, sim3;
  std::string ignored;
  r->metric_valid = alignUmeyama(est, gt, AlignMode::kSE3, &se3, &ignored) &&
                    alignUmeyama(est, gt, AlignMode::kSim3, &sim3, &ignored);
  if (!r->metric_valid) return;
  r->se3_ate_rmse = alignedRmse(est, gt, se3);
  r->sim3_scale = sim3.s;
  r->sim3_ate_rmse = alignedRmse(est, gt, sim3);
}
}  // namespace

bool evaluateTrajectory(const Trajectory& gt, const Trajectory& est, const EvalParams& p, EvalResult* r,
                        std::string* error) {
  *r = EvalResult();
  r->n_gt = gt.size();
  r->n_est = est.size();
  if (gt.stamps.size() != gt.poses.size() || est.stamps.size() != est.poses.size()) {
    if (error) *error = "trajectory stamps / poses size mismatch";
    return false;
  }
  if (!(p.max_dt >= 0.0) || !(p.rpe_delta > 0.0)) {
    if (error) *error = "bad parameters: max_dt must be >= 0 and rpe_delta > 0";
    return false;
  }
  Trajectory g = gt, e = est;
  g.sortAndUnique();
  e.sortAndUnique();
  const auto pairs = associate(g.stamps, e.stamps, p.max_dt);
  r->n_matched = pairs.size();
  r->coverage = g.empty() ? 0.0 : static_cast<double>(pairs.size()) / g.size();
  std::vector<Eigen::Vector3d> pe, pg;
  for (const auto& pr : pairs) {
    pg.push_back(g.poses[pr.first].translation());
    pe.push_back(e.poses[pr.second].translation());
  }
  std::string aerr;
  if (!alignUmeyama(pe, pg, p.align, &r->alignment, &aerr)) {
    if (error) *error = aerr + " (GT " + std::to_string(g.size()) + " poses, estimate " + std::to_string(e.size()) +
                        " poses, max_dt " + std::to_string(p.max_dt) + " s)";
    return false;
  }
  r->scale = r->alignment.s;

  // ATE: || p_gt_i - S(p_est_i) ||.
  std::vector<double> ate;
  std::vector<Eigen::Isometry3d> A, G;
  std::vector<double> stamps;
  for (size_t k = 0; k < pairs.size(); ++k) {
    PoseError pe_k;
    pe_k.stamp = g.stamps[pairs[k].first];
    pe_k.gt = pg[k];
    pe_k.est_aligned = r->alignment.apply(pe[k]);
    pe_k.error = (pe_k.est_aligned - pe_k.gt).norm();
    ate.push_back(pe_k.error);
    r->per_pose.push_back(pe_k);
    A.push_back(r->alignment.apply(e.poses[pairs[k].second]));
    G.push_back(g.poses[pairs[k].first]);
    stamps.push_back(pe_k.stamp);
    if (k > 0) r->gt_length += (pg[k] - pg[k - 1]).norm();
  }
  r->ate = computeStats(ate);
  measureMetricScale(pe, pg, r);

  // RPE over matched pairs (i, j): j = i + delta frames, or the first matched pose with t_j >= t_i + delta.
  std::vector<double> rt, rr;
  for (size_t i = 0; i < A.size(); ++i) {
    size_t j;
    if (p.rpe_delta_frames) {
      j = i + static_cast<size_t>(std::max(1.0, std::round(p.rpe_delta)));
    } else {
      j = static_cast<size_t>(std::lower_bound(stamps.begin() + i, stamps.end(), stamps[i] + p.rpe_delta - 1e-9) - stamps.begin());
    }
    if (j >= A.size()) break;
    const Eigen::Isometry3d E = (G[i].inverse() * G[j]).inverse() * (A[i].inverse() * A[j]);
    rt.push_back(E.translation().norm());
    rr.push_back(Eigen::AngleAxisd(E.linear()).angle() * 180.0 / M_PI);
  }
  r->rpe_trans = computeStats(rt);
  r->rpe_rot = computeStats(rr);
  return true;
}

bool writeErrorsCsv(const std::string& path, const EvalResult& r, std::string* error) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    if (error) *error = path + ": cannot open for writing";
    return false;
  }
  std::fprintf(f, "t,error,est_x,est_y,est_z,gt_x,gt_y,gt_z\n");
  for (const PoseError& e : r.per_pose)
    std::fprintf(f, "%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n", e.stamp, e.error, e.est_aligned.x(), e.est_aligned.y(),
                 e.est_aligned.z(), e.gt.x(), e.gt.y(), e.gt.z());
  const bool ok = std::fclose(f) == 0;
  if (!ok && error) *error = path + ": write failed";
  return ok;
}

namespace {
std::string statsLine(const char* name, const ErrorStats& s, const char* unit) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%-12s rmse %.6f  mean %.6f  median %.6f  std %.6f  min %.6f  max %.6f %s (n=%zu)\n",
                name, s.rmse, s.mean, s.median, s.std, s.min, s.max, unit, s.n);
  return buf;
}
std::string statsJson(const ErrorStats& s) {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "{\"n\": %zu, \"rmse\": %.9g, \"mean\": %.9g, \"median\": %.9g, \"std\": %.9g, \"min\": %.9g, \"max\": %.9g}",
                s.n, s.rmse, s.mean, s.median, s.std, s.min, s.max);
  return buf;
}
}  // namespace

std::string formatSummary(const EvalResult& r, const EvalParams& p) {
  std::ostringstream os;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "poses: GT %zu, estimate %zu, matched %zu (max_dt %.3f s), coverage %.1f %%\n", r.n_gt,
                r.n_est, r.n_matched, p.max_dt, 100.0 * r.coverage);
  os << buf;
  std::snprintf(buf, sizeof(buf), "alignment: %s, scale %.6f, matched GT path length %.3f m\n", alignModeName(p.align),
                r.scale, r.gt_length);
  os << buf;
  os << statsLine("ATE [m]", r.ate, "m");
  if (r.metric_valid) {
    std::snprintf(buf, sizeof(buf),
                  "metric: SE(3) ATE rmse %.6f m (%.3f %% of the path), Sim(3) scale %.6f (ATE rmse %.6f m)\n",
                  r.se3_ate_rmse, r.gt_length > 0 ? 100.0 * r.se3_ate_rmse / r.gt_length : 0.0, r.sim3_scale,
                  r.sim3_ate_rmse);
    os << buf;
  }
  std::snprintf(buf, sizeof(buf), "RPE over %g %s:\n", p.rpe_delta, p.rpe_delta_frames ? "frames" : "s");
  os << buf;
  os << statsLine("  trans", r.rpe_trans, "m");
  os << statsLine("  rot", r.rpe_rot, "deg");
  return os.str();
}

std::string toJson(const EvalResult& r, const EvalParams& p) {
  std::ostringstream os;
  char buf[512];
  os << "{\n";
  std::snprintf(buf, sizeof(buf),
                "  \"align\": \"%s\",\n  \"max_dt\": %.9g,\n  \"rpe_delta\": %.9g,\n  \"rpe_delta_unit\": \"%s\",\n"
                "  \"n_gt\": %zu,\n  \"n_est\": %zu,\n  \"n_matched\": %zu,\n  \"coverage\": %.9g,\n  \"scale\": %.9g,\n"
                "  \"gt_length\": %.9g,\n",
                alignModeName(p.align), p.max_dt, p.rpe_delta, p.rpe_delta_frames ? "frames" : "s", r.n_gt, r.n_est,
                r.n_matched, r.coverage, r.scale, r.gt_length);
  os << buf;
  os << "  \"alignment\": [";
  const Eigen::Matrix4d M = r.alignment.matrix();
  for (int i = 0; i < 16; ++i) {
    std::snprintf(buf, sizeof(buf), "%s%.12g", i ? ", " : "", M(i / 4, i % 4));
    os << buf;
  }
  os << "],\n";
  os << "  \"ate\": " << statsJson(r.ate) << ",\n";
  if (r.metric_valid) {
    std::snprintf(buf, sizeof(buf),
                  "  \"se3_ate_rmse\": %.9g,\n  \"se3_ate_percent_of_path\": %.9g,\n  \"sim3_scale\": %.9g,\n"
                  "  \"sim3_ate_rmse\": %.9g,\n",
                  r.se3_ate_rmse, r.gt_length > 0 ? 100.0 * r.se3_ate_rmse / r.gt_length : 0.0, r.sim3_scale,
                  r.sim3_ate_rmse);
    os << buf;
  }
  os << "  \"rpe_trans\": " << statsJson(r.rpe_trans) << ",\n";
  os << "  \"rpe_rot_deg\": " << statsJson(r.rpe_rot) << "\n}\n";
  return os.str();
}

std::vector<EvalResult> evaluatePerMap(const Trajectory& gt, const Trajectory& est, const std::vector<double>& map_starts,
                                       const EvalParams& params) {
  std::vector<EvalResult> out(std::max<size_t>(1, map_starts.size()));
  for (size_t k = 0; k < out.size(); ++k) {
    const double t0 = k == 0 ? -1e300 : map_starts[k], t1 = k + 1 < map_starts.size() ? map_starts[k + 1] : 1e300;
    Trajectory part;
    for (size_t i = 0; i < est.size(); ++i)
      if (est.stamps[i] >= t0 && est.stamps[i] < t1) part.push_back(est.stamps[i], est.poses[i]);
    std::string error;
    if (!evaluateTrajectory(gt, part, params, &out[k], &error)) out[k] = EvalResult();
  }
  return out;
}

}  // namespace iraf_vo
