// MetricScaleMonitor (tracking/metric_scale_monitor.h): the mean of a stereo map's close pose inliers over a window
// of tracked frames, weak below a threshold; the session's message and the /diagnostics level built on it.
#include <gtest/gtest.h>
#include <iraf_vo/pipeline/run_monitor.h>
#include <iraf_vo/tracking/metric_scale_monitor.h>

using namespace iraf_vo;

namespace {
TrackerParams windowOf(int frames, int min_close) {
  TrackerParams p;
  p.stereo_scale_window_frames = frames;
  p.stereo_scale_min_close_inliers = min_close;
  return p;
}
}  // namespace

TEST(MetricScaleMonitor, WeakOnlyOnAFullWindowBelowTheThreshold) {
  const TrackerParams p = windowOf(4, 15);
  MetricScaleMonitor m(p);
  EXPECT_DOUBLE_EQ(m.mean(), -1.0);
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(m.add(2)) << "window not full at frame " << k;
  EXPECT_FALSE(m.weak());
  EXPECT_TRUE(m.add(2));  // 4 frames, mean 2 < 15: weak, changed
  EXPECT_TRUE(m.weak());
  EXPECT_DOUBLE_EQ(m.mean(), 2.0);
  EXPECT_FALSE(m.add(20));  // 2 2 2 20: mean 6.5, still weak, unchanged
  EXPECT_TRUE(m.weak());
  EXPECT_TRUE(m.add(40));  // 2 2 20 40: 16 >= 15, observed again
  EXPECT_FALSE(m.weak());
  EXPECT_DOUBLE_EQ(m.mean(), 16.0);
}

TEST(MetricScaleMonitor, ReportsTheChangesBothWays) {
  const TrackerParams p = windowOf(2, 10);
  MetricScaleMonitor m(p);
  EXPECT_FALSE(m.add(30));
  EXPECT_FALSE(m.add(30));
  EXPECT_FALSE(m.add(0));  // 30 0: 15
  EXPECT_TRUE(m.add(0));   // 0 0: weak
  EXPECT_TRUE(m.add(40));  // 0 40: 20, observed again
  EXPECT_FALSE(m.weak());
}

TEST(MetricScaleMonitor, RestartAndOff) {
  const TrackerParams p = windowOf(2, 10);
  MetricScaleMonitor m(p);
  m.add(0);
  m.add(0);
  ASSERT_TRUE(m.weak());
  m.restart();  // a new map: no history
  EXPECT_FALSE(m.weak());
  EXPECT_DOUBLE_EQ(m.mean(), -1.0);
  const TrackerParams off = windowOf(2, 0);
  MetricScaleMonitor none(off);
  none.add(0);
  EXPECT_FALSE(none.add(0));
  EXPECT_FALSE(none.weak());
}

TEST(MetricScaleMonitor, DiagnosticsWarnWhileTheScaleIsWeak) {
  TrackerHealthInput in;
  in.state = TrackingState::kTracking;
  in.counters.close_inliers_mean = 40.0;
  HealthReport ok = trackerHealth(in);
  EXPECT_EQ(ok.level, HealthReport::kOk);
  bool listed = false;
  for (const auto& kv : ok.values) listed |= kv.first == "close stereo inliers per frame" && kv.second == "40.00";
  EXPECT_TRUE(listed);
  in.counters.close_inliers_mean = 3.5;
  in.counters.metric_scale_weak = true;
  const HealthReport weak = trackerHealth(in);
  EXPECT_EQ(weak.level, HealthReport::kWarn);
  EXPECT_NE(weak.summary.find("metric scale weakly observed (3.5 close stereo inliers per frame)"), std::string::npos)
      << weak.summary;
  // Monocular: no stereo values.
  TrackerHealthInput mono;
  mono.state = TrackingState::kTracking;
  for (const auto& kv : trackerHealth(mono).values) EXPECT_NE(kv.first, "close stereo inliers per frame");
}
