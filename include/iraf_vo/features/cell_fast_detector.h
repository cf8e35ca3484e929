// FAST-9 corners of one pyramid level with a threshold per cell (ORB-SLAM's cell grid; the thresholds of the
// adaptive FAST threshold, eq. 20, or the fixed ini_th_fast) and the empty-cell retry. ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "iraf_vo/features/cell_grid.h"
#include "iraf_vo/features/feature_frame.h"

namespace iraf_vo {

class CellFastDetector {
 public:
  /// Appends to *candidates (level coordinates; response = FAST score, class_id = the threshold that
  /// admitted the corner) the FAST corners (non-max suppressed) of every cell of `level` whose score is
  /// >= that cell's threshold; cells without any get the corners with score >= retry_th. The threshold of
  /// every scanned cell is appended to *cell_thresholds; st->cells / cells_retried are counted.
  void detect(const cv::Mat& level, const CellGrid& grid, const std::vector<double>& thresholds, double retry_th,
              std::vector<cv::KeyPoint>* candidates, std::vector<double>* cell_thresholds, FeatureStats* st);

 private:
  /// One row of cells: a strip scan at the strip threshold, runs of cells below it, then the retries.
  void detectCellRow(const cv::Mat& level, const CellGrid& grid, int row, int th_retry,
                     std::vector<cv::KeyPoint>* candidates, FeatureStats* st);
  /// The strip threshold T_s minimising the cost model of cv::FAST (see the .cpp) over the sorted cell
  /// thresholds of a row.
  static int stripThreshold(const std::vector<int>& sorted_th, int n_valid);

  std::vector<int> cell_th_, cell_count_, sorted_th_;
  std::vector<cv::KeyPoint> strip_kps_, cell_kps_;
};

}  // namespace iraf_vo
