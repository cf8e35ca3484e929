// The tracker's fast paths against the plain computations they replace (same results, same order).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include "iraf_vo/tracking/frame.h"
#include "tracking_test_utils.h"

using namespace iraf_vo;

namespace {

constexpr double kGridCell = 32.0;  // Frame's search-grid cell (px)

// Plain window search: every valid keypoint in the cells overlapping the window's bounding box, within radius r and
// the octave range, ordered by cell (row-major) and by keypoint index within a cell (the grid's visiting order).
std::vector<int> plainFeaturesInArea(const Frame& f, int width, int height, double u, double v, double r,
                                     int min_octave, int max_octave) {
  const int cols = std::max(1, static_cast<int>(std::ceil(width / kGridCell)));
  const int rows = std::max(1, static_cast<int>(std::ceil(height / kGridCell)));
  const int x0 = std::max(0, static_cast<int>((u - r) / kGridCell));
  const int x1 = std::min(cols - 1, static_cast<int>((u + r) / kGridCell));
  const int y0 = std::max(0, static_cast<int>((v - r) / kGridCell));
  const int y1 = std::min(rows - 1, static_cast<int>((v + r) / kGridCell));
  std::vector<std::tuple<int, int, int>> hits;  // (cell row, cell col, index)
  for (size_t i = 0; i < f.size(); ++i) {
    if (!f.valid[i]) continue;
    const cv::KeyPoint& kp = f.keypoints[i];
    const int cx = std::clamp(static_cast<int>(kp.pt.x / kGridCell), 0, cols - 1);
    const int cy = std::clamp(static_cast<int>(kp.pt.y / kGridCell), 0, rows - 1);
    if (cx < x0 || cx > x1 || cy < y0 || cy > y1) continue;
    if (kp.octave < min_octave || kp.octave > max_octave) continue;
    const double du = kp.pt.x - u, dv = kp.pt.y - v;
    if (du * du + dv * dv <= r * r) hits.emplace_back(cy, cx, static_cast<int>(i));
  }
  std::sort(hits.begin(), hits.end());
  std::vector<int> out;
  for (const auto& h : hits) out.push_back(std::get<2>(h));
  return out;
}

}  // namespace

TEST(TrackingFastPaths, FeaturesInAreaMatchesPlainScanInOrder) {
  const int w = 752, h = 480;
  const test::TestPinhole cam(w, h, 450.0, 376.0, 240.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> ux(-3.f, w + 3.f), uy(-3.f, h + 3.f);
  std::uniform_int_distribution<int> oct(0, 7);
  FeatureFrame in;
  in.width = w;
  in.height = h;
  for (int i = 0; i < 3000; ++i) {
    cv::KeyPoint kp(ux(rng), uy(rng), 31.f);
    kp.octave = oct(rng);
    if (i % 7 == 0 && !in.keypoints.empty()) kp.pt = in.keypoints.back().pt;  // duplicates in one cell
    in.keypoints.push_back(kp);
  }
  in.keypoints[5].pt.x = std::numeric_limits<float>::quiet_NaN();  // invalid: never returned
  in.descriptors = cv::Mat::zeros(static_cast<int>(in.keypoints.size()), 32, CV_8U);
  Frame f;
  std::string error;
  ASSERT_TRUE(Frame::fromFeatures(in, cam, 0, &f, &error)) << error;

  std::uniform_real_distribution<double> qu(-60.0, w + 60.0), qv(-60.0, h + 60.0), qr(0.5, 120.0);
  std::vector<int> fast;
  size_t total = 0;
  for (int q = 0; q < 5000; ++q) {
    const double u = qu(rng), v = qv(rng), r = qr(rng);
    const int lo = oct(rng) - 1, hi = lo + oct(rng) / 2;
    f.featuresInArea(u, v, r, lo, hi, &fast);
    ASSERT_EQ(plainFeaturesInArea(f, w, h, u, v, r, lo, hi), fast) << u << " " << v << " " << r;
    total += fast.size();
  }
  EXPECT_GT(total, 10000u);
  // A Frame copy searches the same.
  const Frame copy = f;
  copy.featuresInArea(100.0, 100.0, 40.0, 0, 7, &fast);
  EXPECT_EQ(plainFeaturesInArea(f, w, h, 100.0, 100.0, 40.0, 0, 7), fast);
}
