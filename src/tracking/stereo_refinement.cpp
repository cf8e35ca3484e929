#include "iraf_vo/tracking/stereo_refinement.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <vector>

namespace iraf_vo {

namespace {

/// A (2 w + 1)^2 patch around `centre` sampled every `step` px (bilinear), minus its mean. false outside the image.
/// The column offsets and weights are computed once per patch, the row pointers once per row (the same arithmetic
/// per sample as computing both at every sample).
bool samplePatch(const cv::Mat& im, const Eigen::Vector2d& centre, double step, int w, std::vector<float>* out) {
  const double reach = w * step + 1.0;
  if (centre.x() - reach < 0.0 || centre.y() - reach < 0.0 || centre.x() + reach > im.cols - 1 ||
      centre.y() + reach > im.rows - 1)
    return false;
  const int n = 2 * w + 1;
  out->resize(static_cast<size_t>(n) * static_cast<size_t>(n));
  cv::AutoBuffer<int, 64> col(static_cast<size_t>(n));  // on the stack up to 64 columns
  cv::AutoBuffer<float, 64> wcol(static_cast<size_t>(n));
  for (int x = -w; x <= w; ++x) {
    const double u = centre.x() + x * step;
    col[x + w] = static_cast<int>(u);
    wcol[x + w] = static_cast<float>(u - col[x + w]);
  }
  double sum = 0.0;
  float* o = out->data();
  for (int y = -w; y <= w; ++y) {
    const double v = centre.y() + y * step;
    const int v0 = static_cast<int>(v);
    const float av = static_cast<float>(v - v0);
    const uint8_t* row0 = im.ptr<uint8_t>(v0);
    const uint8_t* row1 = im.ptr<uint8_t>(v0 + 1);
    for (int c = 0; c < n; ++c) {
      const float au = wcol[c];
      const uint8_t* r0 = row0 + col[c];
      const uint8_t* r1 = row1 + col[c];
      const float s = (1.f - av) * ((1.f - au) * r0[0] + au * r0[1]) + av * ((1.f - au) * r1[0] + au * r1[1]);
      *o++ = s;
      sum += s;
    }
  }
  const float mean = static_cast<float>(sum / static_cast<double>(out->size()));
  for (float& s : *out) s -= mean;
  return true;
}

/// The right patch for a shift along `dir` that changes over the patch: sample (x, y) at centre + step (x, y) + dir
/// (shift + stretch u + shear v), u and v the sample's offset along and across dir [px]. Mean removed; false outside
/// the image.
bool sampleSlanted(const cv::Mat& im, const Eigen::Vector2d& centre, double step, int w, const Eigen::Vector2d& dir,
                   double shift, double stretch, double shear, std::vector<float>* out) {
  const Eigen::Vector2d across(-dir.y(), dir.x());
  const int n = 2 * w + 1;
  out->resize(static_cast<size_t>(n) * static_cast<size_t>(n));
  double sum = 0.0;
  float* o = out->data();
  for (int y = -w; y <= w; ++y)
    for (int x = -w; x <= w; ++x) {
      const Eigen::Vector2d off(x * step, y * step);
      const Eigen::Vector2d q = centre + off + dir * (shift + stretch * off.dot(dir) + shear * off.dot(across));
      if (!(q.x() >= 0.0 && q.y() >= 0.0 && q.x() < im.cols - 1 && q.y() < im.rows - 1)) return false;
      const int u0 = static_cast<int>(q.x()), v0 = static_cast<int>(q.y());
      const float au = static_cast<float>(q.x() - u0), av = static_cast<float>(q.y() - v0);
      const uint8_t* r0 = im.ptr<uint8_t>(v0) + u0;
      const uint8_t* r1 = im.ptr<uint8_t>(v0 + 1) + u0;
      const float s = (1.f - av) * ((1.f - au) * r0[0] + au * r0[1]) + av * ((1.f - au) * r1[0] + au * r1[1]);
      *o++ = s;
      sum += s;
    }
  const float mean = static_cast<float>(sum / static_cast<double>(out->size()));
  for (float& s : *out) s -= mean;
  return true;
}

/// Gauss-Newton on the squared differences of the left patch `pl` and the slanted right patch, over the shift at the
/// centre, its stretch along `dir` and its shear across it (both in px of shift per px, starting at 0). The gradient
/// along dir is the mean of both patches' (ESM; `plp` / `plm`: the left patch moved by +-h along dir). The slopes are
/// damped towards 0 (a patch with texture along one line cannot tell them) and bounded by 1 (45 degrees of shear);
/// the shift moves at most half a step per iteration. false when a patch leaves the image.
bool slantedGaussNewton(const cv::Mat& right, const std::vector<float>& pl, const std::vector<float>& plp,
                        const std::vector<float>& plm, const Eigen::Vector2d& uv_r, const Eigen::Vector2d& dir,
                        double step, int w, double h, int iterations, double* offset) {
  const Eigen::Vector2d across(-dir.y(), dir.x());
  double stretch = 0.0, shear = 0.0;
  std::vector<float> p0, pp, pm;
  for (int it = 0; it < iterations; ++it) {
    if (!sampleSlanted(right, uv_r, step, w, dir, *offset, stretch, shear, &p0) ||
        !sampleSlanted(right, uv_r, step, w, dir, *offset + h, stretch, shear, &pp) ||
        !sampleSlanted(right, uv_r, step, w, dir, *offset - h, stretch, shear, &pm))
      return false;
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    size_t q = 0;
    for (int y = -w; y <= w; ++y)
      for (int x = -w; x <= w; ++x, ++q) {
        const Eigen::Vector2d off(x * step, y * step);
        const double g = ((pp[q] - pm[q]) + (plp[q] - plm[q])) / (4.0 * h);
        const Eigen::Vector3d J(g, g * off.dot(dir), g * off.dot(across));
        H.selfadjointView<Eigen::Lower>().rankUpdate(J);
        b += J * (pl[q] - p0[q]);
      }
    H = H.selfadjointView<Eigen::Lower>();
    if (!(H(0, 0) > 0.0)) break;
    const double damping = 1e-3 * H(0, 0) * (w * step) * (w * step);
    H(1, 1) += damping;
    H(2, 2) += damping;
    const Eigen::Vector3d d = H.ldlt().solve(b);
    if (!d.allFinite()) break;
    *offset += std::max(-0.5 * step, std::min(0.5 * step, d(0)));
    stretch = std::max(-1.0, std::min(1.0, stretch + d(1)));
    shear = std::max(-1.0, std::min(1.0, shear + d(2)));
  }
  return true;
}

/// Gauss-Newton on the squared differences of the left patch `pl` and the right patch over one shift along `dir` for
/// the whole patch (the arguments as for slantedGaussNewton). false when a patch leaves the image.
bool shiftGaussNewton(const cv::Mat& right, const std::vector<float>& pl, const std::vector<float>& plp,
                      const std::vector<float>& plm, const Eigen::Vector2d& uv_r, const Eigen::Vector2d& dir,
                      double step, int w, double h, int iterations, double* offset) {
  std::vector<float> p0, pp, pm;
  for (int it = 0; it < iterations; ++it) {
    const Eigen::Vector2d at = uv_r + dir * *offset;
    if (!samplePatch(right, at, step, w, &p0) || !samplePatch(right, at + dir * h, step, w, &pp) ||
        !samplePatch(right, at - dir * h, step, w, &pm))
      return false;
    double num = 0.0, gg = 0.0;
    for (size_t q = 0; q < pl.size(); ++q) {
      const double g = ((pp[q] - pm[q]) + (plp[q] - plm[q])) / (4.0 * h);
      num += (pl[q] - p0[q]) * g;
      gg += g * g;
    }
    if (!(gg > 0.0)) break;
    *offset += std::max(-0.5 * step, std::min(0.5 * step, num / gg));
  }
  return true;
}

}  // namespace

bool refineAlongEpipolar(const cv::Mat& left, const cv::Mat& right, const Eigen::Vector2d& uv_l,
                         const Eigen::Vector2d& uv_r, const Eigen::Vector2d& direction, double step,
                         Eigen::Vector2d* refined, const EpipolarPatchSearch& search) {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1 || !(step > 0.0) || !direction.allFinite()) return false;
  const int w = search.half_window, L = search.half_range;
  std::vector<float> pl, pr;
  if (!samplePatch(left, uv_l, step, w, &pl)) return false;
  std::vector<double> cost(static_cast<size_t>(2 * L + 1));
  for (int k = -L; k <= L; ++k) {
    if (!samplePatch(right, uv_r + direction * (k * step), step, w, &pr)) return false;
    double sad = 0.0;
    for (size_t q = 0; q < pl.size(); ++q) sad += std::abs(pl[q] - pr[q]);
    cost[static_cast<size_t>(k + L)] = sad;
  }
  const int best = static_cast<int>(std::min_element(cost.begin(), cost.end()) - cost.begin());
  if (best == 0 || best == 2 * L) return false;
  const double c0 = cost[best - 1], c1 = cost[best], c2 = cost[best + 1];
  const double den = 2.0 * (c0 + c2 - 2.0 * c1);
  const double delta = den > 0.0 ? (c0 - c2) / den : 0.0;
  if (!(std::abs(delta) <= 1.0)) return false;
  double offset = (best - L + delta) * step;
  // The parabola through three SAD samples pulls the fit towards the sample grid (up to ~0.1 px at a level pixel of
  // 1.2-1.4). Gauss-Newton on the sum of squared differences, with the mean of the two patches' gradients along the
  // direction (ESM), takes the fit off the grid.
  constexpr double h = 0.5;  // px: the central differences' half span
  std::vector<float> plp, plm;
  if (search.gauss_newton_steps > 0 && (!samplePatch(left, uv_l + direction * h, step, w, &plp) ||
                                        !samplePatch(left, uv_l - direction * h, step, w, &plm)))
    return false;
  const auto gaussNewton = search.slanted ? slantedGaussNewton : shiftGaussNewton;
  if (!gaussNewton(right, pl, plp, plm, uv_r, direction, step, w, h, search.gauss_newton_steps, &offset)) return false;
  *refined = uv_r + direction * offset;
  return true;
}

}  // namespace iraf_vo
