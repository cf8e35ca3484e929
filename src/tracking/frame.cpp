#include "iraf_vo/tracking/frame.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace iraf_vo {

// x86-64's baseline has no POPCNT instruction, so __builtin_popcountll compiles to a libgcc call (22 % of the whole
// VO's CPU time on EuRoC, perf). The popcnt clone is chosen at load time (ifunc) where the CPU has it.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__POPCNT__)
__attribute__((target_clones("popcnt", "default")))
#endif
int hammingDistance(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int k = 0; k < 4; ++k) {
    uint64_t x, y;
    std::memcpy(&x, a + 8 * k, 8);
    std::memcpy(&y, b + 8 * k, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

Descriptor descriptorRow(const cv::Mat& descriptors, int r) {
  Descriptor out;
  std::memcpy(out.data(), descriptors.ptr<uint8_t>(r), 32);
  return out;
}

double octaveSigma(double scale_factor, int octave) {
  const int o = std::max(0, octave);
  // std::pow per call was ~0.3 % of the whole VO (every projected point, match and BA observation). The powers of
  // the scale factor last asked for on this thread are kept (a run has one scale factor): the same std::pow values.
  constexpr int kTabulated = 16;
  thread_local double tabulated_scale = std::numeric_limits<double>::quiet_NaN();
  thread_local std::array<double, kTabulated> powers;
  if (o >= kTabulated) return std::pow(scale_factor, o);
  if (std::memcmp(&scale_factor, &tabulated_scale, sizeof(double)) != 0) {
    for (int k = 0; k < kTabulated; ++k) powers[static_cast<size_t>(k)] = std::pow(scale_factor, k);
    tabulated_scale = scale_factor;
  }
  return powers[static_cast<size_t>(o)];
}

bool Frame::fromFeatures(const FeatureFrame& in, const CameraModel& camera, long index, Frame* f,
                         std::string* error) {
  f->index = index;
  f->stamp = in.stamp;
  f->scale_factor = in.scale_factor > 1.0 ? in.scale_factor : 1.2;
  const size_t n = in.keypoints.size();
  if (n > 0 && (in.descriptors.rows != static_cast<int>(n) || in.descriptors.cols != 32 ||
                in.descriptors.type() != CV_8U)) {
    *error = "descriptors must be N x 32 CV_8U with N = keypoints (" + std::to_string(n) + "), got " +
             std::to_string(in.descriptors.rows) + " x " + std::to_string(in.descriptors.cols);
    return false;
  }
  f->keypoints = in.keypoints;
  f->descriptors = in.descriptors.isContinuous() ? in.descriptors : in.descriptors.clone();
  f->bearings.assign(n, Eigen::Vector3d::Zero());
  f->valid.assign(n, 0);
  f->point_id.assign(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const cv::Point2f& pt = f->keypoints[i].pt;
    if (!std::isfinite(pt.x) || !std::isfinite(pt.y)) continue;
    Eigen::Vector3d b;
    if (camera.unproject(Eigen::Vector2d(pt.x, pt.y), &b) && b.allFinite()) {
      f->bearings[i] = b.normalized();
      f->valid[i] = 1;
    }
  }
  f->buildGrid(camera.width() > 0 ? camera.width() : std::max(1, in.width),
               camera.height() > 0 ? camera.height() : std::max(1, in.height));
  return true;
}

void Frame::buildGrid(int width, int height) {
  cols_ = std::max(1, static_cast<int>(std::ceil(width / cell_)));
  rows_ = std::max(1, static_cast<int>(std::ceil(height / cell_)));
  const size_t n_cells = static_cast<size_t>(cols_ * rows_);
  // Counting sort of the valid keypoints by cell (stable: keypoint order within a cell).
  std::vector<int> cell_of(keypoints.size(), -1);
  grid_start_.assign(n_cells + 1, 0);
  for (size_t i = 0; i < keypoints.size(); ++i) {
    if (!valid[i]) continue;
    const int cx = std::clamp(static_cast<int>(keypoints[i].pt.x / cell_), 0, cols_ - 1);
    const int cy = std::clamp(static_cast<int>(keypoints[i].pt.y / cell_), 0, rows_ - 1);
    cell_of[i] = cy * cols_ + cx;
    ++grid_start_[static_cast<size_t>(cell_of[i]) + 1];
  }
  for (size_t c = 0; c < n_cells; ++c) grid_start_[c + 1] += grid_start_[c];
  grid_entries_.resize(static_cast<size_t>(grid_start_[n_cells]));
  std::vector<int> fill(grid_start_.begin(), grid_start_.end() - 1);
  for (size_t i = 0; i < keypoints.size(); ++i) {
    if (cell_of[i] < 0) continue;
    const cv::KeyPoint& kp = keypoints[i];
    grid_entries_[static_cast<size_t>(fill[static_cast<size_t>(cell_of[i])]++)] = {kp.pt.x, kp.pt.y, kp.octave,
                                                                                    static_cast<int>(i)};
  }
}

void Frame::featuresInArea(double u, double v, double r, int min_octave, int max_octave,
                           std::vector<int>* out) const {
  out->clear();
  const int x0 = std::max(0, static_cast<int>((u - r) / cell_));
  const int x1 = std::min(cols_ - 1, static_cast<int>((u + r) / cell_));
  const int y0 = std::max(0, static_cast<int>((v - r) / cell_));
  const int y1 = std::min(rows_ - 1, static_cast<int>((v + r) / cell_));
  if (x0 > x1 || y0 > y1) return;
  // Cells x0..x1 of row y are one run of entries. Most entries fail the octave test in no predictable pattern, so
  // every entry's index is written and the output advances only for the accepted ones (no branch per entry).
  size_t n_scanned = 0;
  for (int y = y0; y <= y1; ++y)
    n_scanned += static_cast<size_t>(grid_start_[static_cast<size_t>(y * cols_ + x1 + 1)] -
                                     grid_start_[static_cast<size_t>(y * cols_ + x0)]);
  out->resize(n_scanned);
  int* dst = out->data();
  size_t n_kept = 0;
  const double r2 = r * r;
  for (int y = y0; y <= y1; ++y) {
    const GridEntry* e = grid_entries_.data() + grid_start_[static_cast<size_t>(y * cols_ + x0)];
    const GridEntry* end = grid_entries_.data() + grid_start_[static_cast<size_t>(y * cols_ + x1 + 1)];
    for (; e != end; ++e) {
      const double du = e->x - u, dv = e->y - v;
      const bool keep = (e->octave >= min_octave) & (e->octave <= max_octave) & (du * du + dv * dv <= r2);
      dst[n_kept] = e->index;
      n_kept += keep;
    }
  }
  out->resize(n_kept);
}

}  // namespace iraf_vo
