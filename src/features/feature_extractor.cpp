#include "iraf_vo/features/feature_extractor.h"

#include "iraf_vo/common/cpu_clock.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace iraf_vo {

namespace {
}  // namespace

FeatureExtractor::FeatureExtractor() = default;

void FeatureExtractor::buildPyramid(const cv::Mat& gray8, double scale_factor, int n_levels,
                                    std::vector<cv::Mat>* pyramid) {
  pyramid->resize(n_levels);
  (*pyramid)[0] = gray8;
  double scale = 1.0;
  for (int l = 1; l < n_levels; ++l) {
    scale *= scale_factor;
    const cv::Size sz(static_cast<int>(std::lround(gray8.cols / scale)),
                      static_cast<int>(std::lround(gray8.rows / scale)));
    if (sz.width < 1 || sz.height < 1) {
      (*pyramid)[l] = cv::Mat();
      continue;
    }
    cv::resize((*pyramid)[l - 1], (*pyramid)[l], sz, 0, 0, cv::INTER_LINEAR);
  }
}

void FeatureExtractor::checkInput(const cv::Mat& gray8, const FeatureParams& p) {
  if (gray8.empty()) throw std::invalid_argument("FeatureExtractor: empty image");
  if (gray8.type() != CV_8UC1)
    throw std::invalid_argument("FeatureExtractor: expected CV_8UC1 image, got type " + std::to_string(gray8.type()));
  const std::string err = validate(p);
  if (!err.empty()) throw std::invalid_argument("FeatureExtractor: invalid parameters: " + err);
}

FeatureFrame FeatureExtractor::extract(const cv::Mat& gray8, double stamp, const FeatureParams& p,
                                       CulledFeatures* culled) {
  checkInput(gray8, p);
  FeatureFrame frame;
  frame.stamp = stamp;
  frame.width = gray8.cols;
  frame.height = gray8.rows;
  frame.scale_factor = p.scale_factor;
  FeatureStats& st = frame.stats;
  if (culled) {
    culled->keypoints.clear();
    culled->stability.clear();
  }

  const double t_detect = threadCpuMs();
  // Level 0 is copied so the frame never aliases caller memory kept in pyramid().
  gray8.copyTo(level0_);
  buildPyramid(level0_, p.scale_factor, p.n_levels, &pyramid_);
  st.ms_pyramid = threadCpuMsSince(t_detect);
  const std::vector<int> quota = featuresPerLevel(p.n_features, p.scale_factor, p.n_levels);
  cell_thresholds_.clear();
  level_kps_.resize(p.n_levels);
  all_kps_.clear();
  for (int l = 0; l < p.n_levels; ++l) detectLevel(l, quota[l], p, &st);
  st.detected = static_cast<int>(all_kps_.size());
  st.ms_detect = threadCpuMsSince(t_detect) - st.ms_threshold;

  const CullResult cr = cull(gray8.size(), p, &st);

  const double t_desc = threadCpuMs();
  describeKept(cr, p, &frame, culled);
  st.ms_describe = threadCpuMsSince(t_desc);
  st.ms_detect += st.ms_describe;
  summarizeCellThresholds(&st);
  return frame;
}

void FeatureExtractor::detectLevel(int l, int quota, const FeatureParams& p, FeatureStats* st) {
  std::vector<cv::KeyPoint>& kps = level_kps_[l];
  kps.clear();
  const cv::Mat& img = pyramid_[l];
  const CellGrid grid = cellGridOfLevel(img.cols, img.rows, p.cell_size);
  if (img.empty() || grid.empty()) return;

  const double t_th = threadCpuMs();
  const double retry_th = threshold_estimator_.estimate(img, grid, p, l == 0, st, &thresholds_);  // eqs. 13-20
  st->ms_threshold += threadCpuMsSince(t_th);

  candidates_.clear();
  const double t_fast = threadCpuMs();
  fast_detector_.detect(img, grid, thresholds_, retry_th, p.fast_path, &candidates_, &cell_thresholds_, st);
  st->ms_fast += threadCpuMsSince(t_fast);
  st->candidates += static_cast<int>(candidates_.size());

  // Quad-tree distribution with the level's quota; keypoints keep level coordinates until description.
  kps = distributeQuadTree(candidates_, static_cast<float>(grid.min_border), static_cast<float>(grid.min_border),
                           static_cast<float>(grid.max_x), static_cast<float>(grid.max_y), quota);
  double level_scale = 1.0;  // scale_factor^l, accumulated as the pyramid is built
  for (int i = 0; i < l; ++i) level_scale *= p.scale_factor;
  const float scale = static_cast<float>(level_scale);
  for (cv::KeyPoint& kp : kps) {
    kp.octave = l;
    kp.size = static_cast<float>(kOrbPatchSize * level_scale);
    cv::KeyPoint k0 = kp;
    k0.pt *= scale;
    all_kps_.push_back(k0);
  }
}

CullResult FeatureExtractor::cull(const cv::Size& image_size, const FeatureParams& p, FeatureStats* st) {
  const double t_cull = threadCpuMs();
  CullResult cr = cullKeypoints(all_kps_, pyramid_, image_size, p);  // eqs. 21-23
  st->culled = cr.culled;
  st->ms_cull = threadCpuMsSince(t_cull);
  return cr;
}

void FeatureExtractor::describeKept(const CullResult& cr, const FeatureParams& p, FeatureFrame* frame,
                                    CulledFeatures* culled) {
  const size_t n_kept = all_kps_.size() - cr.culled;
  frame->keypoints.reserve(n_kept);
  frame->stability.reserve(n_kept);
  frame->descriptors.create(static_cast<int>(n_kept), 32, CV_8U);
  size_t g = 0;  // index into all_kps_ (= level_kps_ concatenated)
  int row = 0;
  for (int l = 0; l < p.n_levels; ++l) {
    level_batch_.clear();
    batch_index_.clear();
    const cv::Mat& img = pyramid_[l];
    for (size_t i = 0; i < level_kps_[l].size(); ++i, ++g) {
      if (!cr.keep[g] && !culled) continue;
      const float angle = intensityCentroidAngle(img, level_kps_[l][i].pt);
      all_kps_[g].angle = angle;
      if (!cr.keep[g]) {
        culled->keypoints.push_back(all_kps_[g]);
        culled->stability.push_back(cr.stability[g]);
        continue;
      }
      cv::KeyPoint k = level_kps_[l][i];
      k.angle = angle;
      level_batch_.push_back(k);
      batch_index_.push_back(g);
    }
    if (level_batch_.empty()) continue;
    const int n_in = static_cast<int>(level_batch_.size());
    cv::Mat rows = frame->descriptors.rowRange(row, row + n_in);
    describer_.compute(img, level_batch_, &rows);
    row += n_in;
    for (size_t i : batch_index_) {
      frame->keypoints.push_back(all_kps_[i]);
      frame->stability.push_back(cr.stability[i]);
    }
  }
}

void FeatureExtractor::summarizeCellThresholds(FeatureStats* st) {
  if (cell_thresholds_.empty()) return;
  auto mm = std::minmax_element(cell_thresholds_.begin(), cell_thresholds_.end());
  st->cell_threshold_min = *mm.first;
  st->cell_threshold_max = *mm.second;
  auto mid = cell_thresholds_.begin() + cell_thresholds_.size() / 2;
  std::nth_element(cell_thresholds_.begin(), mid, cell_thresholds_.end());
  st->cell_threshold_median = *mid;
}

}  // namespace iraf_vo
