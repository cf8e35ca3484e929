// Adaptive FAST threshold of IRAF-SLAM (paper II-B, eqs. 13-20): building blocks. ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "iraf_vo/features/cell_grid.h"
#include "iraf_vo/features/feature_frame.h"
#include "iraf_vo/features/feature_params.h"

namespace iraf_vo {

using Histogram256 = std::array<uint32_t, 256>;

/// Adds the intensities of a CV_8UC1 image (or ROI) to *h.
void accumulateHistogram(const cv::Mat& gray, Histogram256* h);

/// eq. (13): F_h = -sum_i P(i) log2 P(i), in BITS (log base 2): 0 for a constant image, 8 (= log2 256)
/// for a uniform histogram. Returns 0 for an empty histogram.
double histogramEntropy(const Histogram256& h);

/// eq. (14): F_g = 1/(N M) sum sqrt(I_x^2 + I_y^2), I_x, I_y = 3x3 Sobel (cv::spatialGradient,
/// replicated border). `sobel_rows` is a scratch buffer (4 int16 rows) reused between calls.
double meanGradientMagnitude(const cv::Mat& gray, cv::Mat* sobel_rows);
double meanGradientMagnitude(const cv::Mat& gray);
/// The same F_g from cv::spatialGradient's planes (the reference of the row-wise Sobel above, for tests).
double meanGradientMagnitudeReference(const cv::Mat& gray);
/// meanGradientMagnitude's row kernel: AVX2 (16 pixels per step, where the CPU has it; the default) or the
/// baseline SIMD build. Both give the same F_g bit for bit; for tests. Returns whether AVX2 is now in use.
bool gradientUseAvx2(bool allowed);

/// eq. (15): F_t^g = alpha * F_h + beta * F_g.
inline double globalThreshold(double f_h, double f_g, double alpha, double beta) { return alpha * f_h + beta * f_g; }

/// eqs. (16)-(18): Otsu threshold t_o = argmax_t sigma_c^2(t),
/// sigma_c^2(t) = (mu_T P_t(t) - mu_t(t))^2 / (P_t(t) (1 - P_t(t))). Pixels <= t_o form the lower class.
/// For an empty or single-valued histogram returns that value (or 0).
int otsuThreshold(const Histogram256& h);
/// The same t_o by one sequential scan over every t (the definition; otsuThreshold evaluates sigma_c^2 with
/// SIMD and rescans only near its maximum, bit-identical results, test AdaptiveThreshold.OtsuEqualsReference).
int otsuThresholdReference(const Histogram256& h);

/// eq. (19): F_t^l = delta * |I_m - t_o|.
inline double localThreshold(double i_m, double t_o, double delta) { return delta * std::abs(i_m - t_o); }

/// mean over the histogram's pixels of |I - t_o|: eq. (19)'s |I_m - t_o| averaged over every position of I_m
/// (FeatureParams::cell_mean_contrast). 0 for an empty histogram.
double meanDeviationFrom(const Histogram256& h, int t_o);

/// eq. (20): F_t = clip(F_t^l, F_t,min^l, F_t^g). When F_t^g < F_t,min the lower bound wins
/// (the result is never below ft_min).
inline double clipThreshold(double ft_local, double ft_min, double ft_global) {
  const double hi = ft_global > ft_min ? ft_global : ft_min;
  return ft_local < ft_min ? ft_min : (ft_local > hi ? hi : ft_local);
}

/// The FAST threshold of every cell of a level: eq. (20) F_t per cell with adaptive_threshold on,
/// ini_th_fast otherwise. Scratch buffers are kept between calls (no per-frame allocation).
class CellThresholdEstimator {
 public:
  /// Fills *thresholds (row-major, grid.cells()) for `level`. On level 0 (level0 = true) also computes the
  /// frame's global metrics F_h, F_g, F_t^g (eqs. 13-15) into *st, used as the upper clip of every level.
  /// Returns the retry threshold for cells where F_t finds nothing (ft_min, or min_th_fast when off).
  double estimate(const cv::Mat& level, const CellGrid& grid, const FeatureParams& p, bool level0, FeatureStats* st,
                  std::vector<double>* thresholds);

 private:
  /// Otsu t_o (eqs. 16-18) and the contrast |I_m - t_o| of eq. (19) of every cell (I_m: the centre_window patch,
  /// or every pixel of the cell when cell_mean); adds the cells' histograms to *level_hist if given.
  void measureCells(const cv::Mat& level, const CellGrid& grid, int center_window, bool cell_mean,
                    Histogram256* level_hist);

  std::vector<int> otsu_;
  std::vector<double> contrast_;  // |I_m - t_o| per cell
  cv::Mat sobel_rows_;  // scratch of meanGradientMagnitude
};

}  // namespace iraf_vo
