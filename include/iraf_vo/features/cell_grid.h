// The FAST cell grid of one pyramid level (ORB-SLAM): cells of ~cell_size px tiling the detection area
// [min_border, max_x) x [min_border, max_y), which keeps keypoints >= 16 px (+3 for the FAST circle) from the
// level border. The cells are also the subregions of the adaptive threshold (eqs. 16-19). ROS-free.
#pragma once

#include <algorithm>

namespace iraf_vo {

constexpr int kEdgeThreshold = 19;  // ORB-SLAM EDGE_THRESHOLD: keypoints stay >= 19 px from the level border

struct CellGrid {
  int min_border = 0, max_x = 0, max_y = 0;  // detection area of the level
  int n_cols = 0, n_rows = 0;                 // cells
  int w_cell = 0, h_cell = 0;                 // cell side [px of the level]
  bool empty() const { return n_cols == 0 || n_rows == 0; }
  int cells() const { return n_cols * n_rows; }
  int x0(int j) const { return min_border + j * w_cell; }
  int y0(int i) const { return min_border + i * h_cell; }
  /// Column of the cell holding FAST corner x (the 3-px FAST margin is inside the first cell).
  int colOf(float x) const { return std::min(n_cols - 1, std::max(0, static_cast<int>(x - min_border - 3) / w_cell)); }
};

/// The grid of a cols x rows level image; empty() when the level is too small to detect on.
inline CellGrid cellGridOfLevel(int cols, int rows, int cell_size) {
  CellGrid g;
  g.min_border = kEdgeThreshold - 3;
  g.max_x = cols - kEdgeThreshold + 3;
  g.max_y = rows - kEdgeThreshold + 3;
  const int width = g.max_x - g.min_border, height = g.max_y - g.min_border;
  if (cols <= 0 || rows <= 0 || width < 8 || height < 8) return CellGrid();
  g.n_cols = std::max(1, width / cell_size);
  g.n_rows = std::max(1, height / cell_size);
  g.w_cell = (width + g.n_cols - 1) / g.n_cols;
  g.h_cell = (height + g.n_rows - 1) / g.n_rows;
  return g;
}

}  // namespace iraf_vo
