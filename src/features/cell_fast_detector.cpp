#include "iraf_vo/features/cell_fast_detector.h"

#include "iraf_vo/features/fast9.h"

#include <opencv2/features2d.hpp>

#include <algorithm>
#include <cmath>

namespace iraf_vo {

// ORB-SLAM runs cv::FAST once per cell (ROI = cell + 3 px each side). cv::FAST on 41-px-wide ROIs is
// ~3x slower per pixel than on full rows (SIMD tails, per-call setup), so each row of cells ("strip")
// is scanned in one call at the strip's threshold T_s and every corner is kept iff its FAST score
// >= its cell's threshold. This is exactly FAST at the cell threshold: a corner at threshold t is a
// corner at any t' < t with score >= t, and non-max suppression only compares corners' scores.
// T_s is chosen per strip (cost model below) so a few low-threshold cells do not make FAST scan the
// whole strip at a low threshold; runs of cells below T_s get their own call.
// These calls define the output; they are computed by one detectFast9 pass per strip (scanStripAndRuns,
// bit for bit the same corners) and detectFast9 at one threshold (fastAt = cv::FAST) for the retries.
// T_s keeps the cost model fitted to cv::FAST because T_s decides the run ROIs and so the output.
// Empty cells are retried at retry_th (ORB-SLAM's minThFAST retry). Each pixel belongs to one cell,
// so unlike ORB-SLAM's overlapping ROIs no corner is reported twice.
// That is the reference path (FeatureParams::fast_path = false). The fast path (default) scans each strip
// once with detectFast9, whose threshold is per column, i.e. every cell's own F_t: no call at a threshold
// below the cell's, no per-run calls. Both give the same corners except where non-max suppression sees a
// neighbour across a run's ROI border (reference) that the one pass sees (fast path); with equal thresholds
// in a strip (adaptive_threshold off) they are identical.
// (Measured alternative: one cv::FAST pass over the whole level at its lowest cell threshold,
// filtered by score, costs 2.7x the scan at 20 on EuRoC level 0 when that lowest threshold is ft_min = 7,
// which is the case on most frames: slower than the strips.)
void CellFastDetector::detect(const cv::Mat& img, const CellGrid& g, const std::vector<double>& thresholds,
                              double retry_th, bool one_pass, std::vector<cv::KeyPoint>* candidates,
                              std::vector<double>* cell_thresholds, FeatureStats* st) {
  const int th_retry = std::max(1, static_cast<int>(std::lround(retry_th)));
  cell_th_.resize(g.n_cols);
  cell_count_.resize(g.n_cols);
  sorted_th_.resize(g.n_cols);
  for (int i = 0; i < g.n_rows; ++i) {
    if (g.y0(i) >= g.max_y - 3) continue;
    for (int j = 0; j < g.n_cols; ++j) {
      cell_count_[j] = 0;
      if (g.x0(j) >= g.max_x - 3) {
        cell_th_[j] = -1;  // no pixel left for this cell (ORB-SLAM skips it too)
        continue;
      }
      cell_th_[j] = std::max(1, static_cast<int>(std::lround(thresholds[i * g.n_cols + j])));
      cell_thresholds->push_back(thresholds[i * g.n_cols + j]);
      ++st->cells;
    }
    detectCellRow(img, g, i, th_retry, one_pass, candidates, st);
  }
}

void CellFastDetector::fastAt(const cv::Mat& roi, int t, std::vector<cv::KeyPoint>* kps) {
  // detectFast9 with every column at t gives exactly cv::FAST(roi, kps, t, true) (same corners, scores,
  // order; test Fast9.EqualsCvFastForOneThreshold), ~2x faster on EuRoC strips.
  col_th_.assign(roi.cols, static_cast<uint8_t>(std::min(t, 255)));
  detectFast9(roi, col_th_.data(), kps, &fast9_buffers_);
}

int CellFastDetector::stripThreshold(const std::vector<int>& sorted_th, int n_valid) {
  // T_s: the cell threshold minimising a cost model of cv::FAST measured on EuRoC (per cell, us):
  // scanning a cell inside a strip at threshold T ~ 0.5 + 60 / T, its own call ~ 5 + 1.2 (0.5 + 60 / T).
  // (Always scanning at the strip minimum was 13 % slower on EuRoC, constants 1 / 1.0 or 20 / 2 2-6 %.)
  int t_strip = sorted_th[0];
  double best = 1e30, below = 0.0;
  for (int k = 0; k < n_valid; ++k) {
    const double t = sorted_th[k];
    if (k == 0 || sorted_th[k] != sorted_th[k - 1]) {
      const double cost = n_valid * (0.5 + 60.0 / t) + below;
      if (cost < best) {
        best = cost;
        t_strip = sorted_th[k];
      }
    }
    below += 5.0 + 1.2 * (0.5 + 60.0 / t);
  }
  return t_strip;
}

void CellFastDetector::detectCellRow(const cv::Mat& img, const CellGrid& g, int i, int th_retry, bool one_pass,
                                     std::vector<cv::KeyPoint>* candidates, FeatureStats* st) {
  const int ini_y = g.y0(i);
  const int max_y = std::min(ini_y + g.h_cell + 6, g.max_y);
  int n_valid = 0;
  for (int j = 0; j < g.n_cols; ++j)
    if (cell_th_[j] >= 0) sorted_th_[n_valid++] = cell_th_[j];
  if (n_valid == 0) return;
  const cv::Mat strip = img(cv::Rect(g.min_border, ini_y, g.max_x - g.min_border, max_y - ini_y));
  int t_strip = 256;  // no strip corners below a cell's threshold (one pass)
  if (one_pass) {
    scanStripOnePass(strip, g, ini_y, candidates);
  } else {
    std::sort(sorted_th_.begin(), sorted_th_.begin() + n_valid);
    t_strip = stripThreshold(sorted_th_, n_valid);
    scanStripAndRuns(strip, g, ini_y, t_strip, candidates);
  }
  retryEmptyCells(img, g, ini_y, max_y, th_retry, t_strip, candidates, st);
}

void CellFastDetector::scanStripOnePass(const cv::Mat& strip, const CellGrid& g, int ini_y,
                                        std::vector<cv::KeyPoint>* candidates) {
  // Every column gets its cell's threshold: one FAST pass applies F_t of eq. (20) per cell.
  col_th_.resize(strip.cols);
  for (int c = 0; c < strip.cols; ++c) {
    const int th = cell_th_[g.colOf(static_cast<float>(g.min_border + c))];
    col_th_[c] = static_cast<uint8_t>(th < 0 ? 255 : std::min(th, 255));
  }
  detectFast9(strip, col_th_.data(), &strip_kps_, &fast9_buffers_);
  for (cv::KeyPoint& kp : strip_kps_) {
    const int j = g.colOf(kp.pt.x + g.min_border);
    kp.pt.x += g.min_border;
    kp.pt.y += ini_y;
    kp.class_id = cell_th_[j];
    candidates->push_back(kp);
    ++cell_count_[j];
  }
}

void CellFastDetector::scanStripAndRuns(const cv::Mat& strip, const CellGrid& g, int ini_y, int t_strip,
                                        std::vector<cv::KeyPoint>* candidates) {
  // The reference: cv::FAST over the strip at T_s (corners of cells below T_s dropped), then per run of
  // adjacent cells below T_s one cv::FAST call at the run's lowest threshold t_run on the run's ROI; every
  // corner is kept iff its score >= its cell's threshold F_t. Here all of that is ONE detectFast9 pass over
  // the strip, with non-max suppression walls at each run's first / last detection column (its ROI ends
  // there) and column c scanned at min F_t over c and the neighbours whose NMS sees c. Identical output:
  //  - a pixel's FAST score s does not depend on the threshold or the ROI (>= 3 px inside), only NMS does;
  //  - NMS keeps a corner iff s > the score of every neighbour that is a corner of the same call; a neighbour
  //    scoring below s never suppresses, so a neighbour matters only when its score >= s >= the corner's F_t,
  //    and every neighbour column is scanned at a threshold <= that F_t. Which neighbours are seen is the
  //    call's ROI: the whole strip for strip corners, the run's columns for run corners (walls).
  walls_.assign(strip.cols, 0);
  runs_.clear();
  const int x_last = g.max_x - 3;  // detection columns of the strip: [min_border + 3, max_x - 3)
  for (int j = 0; j < g.n_cols;) {
    if (cell_th_[j] < 0 || cell_th_[j] >= t_strip) {
      ++j;
      continue;
    }
    int j1 = j;
    while (j1 + 1 < g.n_cols && cell_th_[j1 + 1] >= 0 && cell_th_[j1 + 1] < t_strip) ++j1;
    // The run's ROI [x0(j), min(x0(j1 + 1) + 6, max_x)) detects columns [x0(j) + 3, min(x0(j1 + 1) + 3, max_x - 3)).
    const int xb = g.x0(j) + 3 - g.min_border, xe = std::min(g.x0(j1 + 1) + 3, x_last) - g.min_border;
    if (xe > xb) {
      walls_[xb] |= kWallLeft;
      walls_[xe - 1] |= kWallRight;
    }
    runs_.push_back({j, j1, xb + g.min_border, xe + g.min_border});
    j = j1 + 1;
  }
  // F_t of every detection column (its cell), then the scan threshold: min over the column and the
  // neighbours that see it.
  own_th_.assign(strip.cols, 255);
  cell_of_col_.assign(strip.cols, 0);
  for (int j = 0; j < g.n_cols; ++j) {  // cell j holds detection columns [x0(j) + 3, x0(j + 1) + 3) (colOf)
    const int cb = j == 0 ? 3 : g.x0(j) + 3 - g.min_border;
    const int ce = std::min(j + 1 == g.n_cols ? strip.cols - 3 : g.x0(j + 1) + 3 - g.min_border, strip.cols - 3);
    if (ce <= cb) continue;
    std::fill(own_th_.begin() + cb, own_th_.begin() + ce, static_cast<uint8_t>(cell_th_[j] < 0 ? 255 : std::min(255, cell_th_[j])));
    std::fill(cell_of_col_.begin() + cb, cell_of_col_.begin() + ce, j);
  }
  col_th_.resize(strip.cols);
  for (int c = 0; c < strip.cols; ++c) {
    uint8_t t = own_th_[c];
    if (c > 0 && !(walls_[c - 1] & kWallRight)) t = std::min(t, own_th_[c - 1]);
    if (c + 1 < strip.cols && !(walls_[c + 1] & kWallLeft)) t = std::min(t, own_th_[c + 1]);
    col_th_[c] = t;
  }
  detectFast9(strip, col_th_.data(), &strip_kps_, &fast9_buffers_, walls_.data());
  for (cv::KeyPoint& kp : strip_kps_) {
    kp.pt.x += g.min_border;
    kp.pt.y += ini_y;
  }
  // Candidates in the reference's order: the strip call's corners (row-major), then each run's (row-major).
  // A run's detection columns are exactly those of its cells, so one pass sorts each corner by its cell:
  // a cell at or above T_s (strip call) or a run's cell (kept aside for that run).
  run_of_cell_.assign(g.n_cols, -1);
  for (size_t r = 0; r < runs_.size(); ++r)
    for (int j = runs_[r].j0; j <= runs_[r].j1; ++j) run_of_cell_[j] = static_cast<int>(r);
  if (run_kps_.size() < runs_.size()) run_kps_.resize(runs_.size());
  for (size_t r = 0; r < runs_.size(); ++r) run_kps_[r].clear();
  for (int k = 0; k < static_cast<int>(strip_kps_.size()); ++k) {
    const cv::KeyPoint& kp = strip_kps_[k];
    const int j = cell_of_col_[static_cast<int>(kp.pt.x) - g.min_border];  // = g.colOf(kp.pt.x)
    if (kp.response < cell_th_[j]) continue;
    if (cell_th_[j] >= t_strip) {
      candidates->push_back(kp);
      candidates->back().class_id = cell_th_[j];
      ++cell_count_[j];
    } else if (run_of_cell_[j] >= 0) {
      run_kps_[run_of_cell_[j]].push_back(k);
    }
  }
  for (size_t r = 0; r < runs_.size(); ++r) {
    for (int k : run_kps_[r]) {
      const cv::KeyPoint& kp = strip_kps_[k];
      const int j = cell_of_col_[static_cast<int>(kp.pt.x) - g.min_border];
      candidates->push_back(kp);
      candidates->back().class_id = cell_th_[j];
      ++cell_count_[j];
    }
  }
}

void CellFastDetector::stripRetryCorners(const cv::Mat& strip, const CellGrid& g, int ini_y, int j, int th_retry,
                                         std::vector<cv::KeyPoint>* candidates) {
  // The reference's retry of empty cell j (not in a run) at retry_th >= T_s: the strip call's corners in
  // cell j with score >= retry_th. The scan above only holds corners down to F_t, so the cell's columns
  // are scanned again at retry_th with one column on each side (the neighbours its NMS sees; a neighbour
  // matters only when its score >= retry_th) and 3 px for the circle, clipped to the strip.
  const int xb = g.x0(j) + 3 - g.min_border;
  const int xe = std::min(j + 1 < g.n_cols ? g.x0(j + 1) + 3 : g.max_x - 3, g.max_x - 3) - g.min_border;
  const int lo = std::max(0, xb - 4), hi = std::min(strip.cols, xe + 4);
  fastAt(strip.colRange(lo, hi), th_retry, &cell_kps_);
  for (const cv::KeyPoint& kp : cell_kps_) {
    const int x = static_cast<int>(kp.pt.x) + lo;
    if (x < xb || x >= xe) continue;
    candidates->push_back(kp);
    candidates->back().pt.x = static_cast<float>(x + g.min_border);
    candidates->back().pt.y += ini_y;
    candidates->back().class_id = th_retry;
  }
}

void CellFastDetector::retryEmptyCells(const cv::Mat& img, const CellGrid& g, int ini_y, int max_y, int th_retry,
                                       int t_strip, std::vector<cv::KeyPoint>* candidates, FeatureStats* st) {
  // Retry of the empty cells at th_retry (only where it is below the cell's threshold).
  for (int j = 0; j < g.n_cols; ++j) {
    const int th = cell_th_[j];
    if (th < 0 || cell_count_[j] > 0 || th_retry >= th) continue;
    ++st->cells_retried;
    if (t_strip <= th_retry) {  // the reference takes them from its strip call
      stripRetryCorners(img(cv::Rect(g.min_border, ini_y, g.max_x - g.min_border, max_y - ini_y)), g, ini_y, j,
                        th_retry, candidates);
      continue;
    }
    const int ini_x = g.x0(j);
    const int max_x = std::min(ini_x + g.w_cell + 6, g.max_x);
    const cv::Mat cell = img(cv::Rect(ini_x, ini_y, max_x - ini_x, max_y - ini_y));
    fastAt(cell, th_retry, &cell_kps_);
    for (cv::KeyPoint& kp : cell_kps_) {
      kp.pt.x += ini_x;
      kp.pt.y += ini_y;
      kp.class_id = th_retry;
      candidates->push_back(kp);
    }
    cell_count_[j] = static_cast<int>(cell_kps_.size());
  }
}

}  // namespace iraf_vo
