// FAST-9 corners of one pyramid level with a threshold per cell (ORB-SLAM's cell grid; the thresholds of the
// adaptive FAST threshold, eq. 20, or the fixed ini_th_fast) and the empty-cell retry. ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "iraf_vo/features/cell_grid.h"
#include "iraf_vo/features/fast9.h"
#include "iraf_vo/features/feature_frame.h"

namespace iraf_vo {

class CellFastDetector {
 public:
  /// Appends to *candidates (level coordinates; response = FAST score, class_id = the threshold that
  /// admitted the corner) the FAST corners (non-max suppressed) of every cell of `level` whose score is
  /// >= that cell's threshold; cells without any get the corners with score >= retry_th. The threshold of
  /// every scanned cell is appended to *cell_thresholds; st->cells / cells_retried are counted.
  /// one_pass: each row of cells in one FAST pass with per-column thresholds (fast path); false: the
  /// reference path, cv::FAST per strip at a strip threshold plus runs of lower-threshold cells.
  void detect(const cv::Mat& level, const CellGrid& grid, const std::vector<double>& thresholds, double retry_th,
              bool one_pass, std::vector<cv::KeyPoint>* candidates, std::vector<double>* cell_thresholds,
              FeatureStats* st);

  /// The strip threshold T_s minimising the cost model of cv::FAST (see the .cpp) over the sorted cell
  /// thresholds of a row (the first n_valid entries of sorted_th).
  static int stripThreshold(const std::vector<int>& sorted_th, int n_valid);

 private:
  /// One row of cells: the corners at the cells' thresholds, then the retries of empty cells.
  void detectCellRow(const cv::Mat& level, const CellGrid& grid, int row, int th_retry, bool one_pass,
                     std::vector<cv::KeyPoint>* candidates, FeatureStats* st);
  /// Fast path: detectFast9 over the strip with every column at its cell's threshold.
  void scanStripOnePass(const cv::Mat& strip, const CellGrid& grid, int ini_y, std::vector<cv::KeyPoint>* candidates);
  /// Reference path: the corners of cv::FAST over the strip at t_strip and per run of cells below t_strip
  /// (one call per run, on the run's ROI), computed in one detectFast9 pass (see the .cpp).
  void scanStripAndRuns(const cv::Mat& strip, const CellGrid& grid, int ini_y, int t_strip,
                        std::vector<cv::KeyPoint>* candidates);
  /// Empty cells (where retry_th < their threshold) rescanned at retry_th; from the strip scan when it ran at
  /// t_strip <= retry_th.
  void retryEmptyCells(const cv::Mat& level, const CellGrid& grid, int ini_y, int max_y, int th_retry, int t_strip,
                       std::vector<cv::KeyPoint>* candidates, FeatureStats* st);
  /// Appends the reference strip call's corners of empty cell j with score >= th_retry (class_id th_retry).
  void stripRetryCorners(const cv::Mat& strip, const CellGrid& grid, int ini_y, int j, int th_retry,
                         std::vector<cv::KeyPoint>* candidates);
  /// cv::FAST(roi, *kps, t, true), computed by detectFast9 with one threshold for every column.
  void fastAt(const cv::Mat& roi, int t, std::vector<cv::KeyPoint>* kps);
  std::vector<int> cell_th_, cell_count_, sorted_th_;
  std::vector<cv::KeyPoint> strip_kps_, cell_kps_;
  struct Run {
    int j0, j1;            // cells j0..j1 of the row, all below the strip threshold
    int x_begin, x_end;    // their detection columns [level px]
  };
  std::vector<Run> runs_;
  std::vector<uint8_t> col_th_, own_th_, walls_;
  std::vector<int> cell_of_col_;  // strip column -> cell (colOf)
  std::vector<int> run_of_cell_;  // cell of the row -> its run in runs_ (-1: none)
  std::vector<std::vector<int>> run_kps_;  // per run: indices of its corners in strip_kps_ (row-major)
  Fast9Buffers fast9_buffers_;
};

}  // namespace iraf_vo
