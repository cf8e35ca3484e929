// Tracking results -> messages (src/ros/tracking_conversion.cpp): TrackingStatus.reason while initializing, the
// epoch, tracking_events, an unknown twist.
#include <gtest/gtest.h>

#include "iraf_vo/ros/tracking_conversion.h"

using namespace iraf_vo;

TEST(TrackingConversion, StatusCarriesTheInitializationReason) {
  SessionStep step;
  step.tracked_frame = true;
  step.result.state = TrackingState::kInitializing;
  step.result.init_status = "too few matches with the reference frame (12 < 100)";
  std_msgs::Header h;
  const TrackingStatusPtr init = toStatusMsg(step, h, 500, 1.0);
  EXPECT_EQ(init->state_name, "INITIALIZING");
  EXPECT_EQ(init->reason, "initializing: too few matches with the reference frame (12 < 100)");
  // A rejection by the health monitor comes first; a tracked frame has no reason.
  step.result.state = TrackingState::kLost;
  step.result.rejected = "reprojection error 9.1 px";
  EXPECT_EQ(toStatusMsg(step, h, 500, 1.0)->reason, "reprojection error 9.1 px");
  step.result = TrackResult();
  step.result.state = TrackingState::kTracking;
  EXPECT_EQ(toStatusMsg(step, h, 500, 1.0)->reason, "");
}

TEST(TrackingConversion, EpochAndEvents) {
  SessionStep step;
  step.result.state = TrackingState::kTracking;
  step.counters.epoch = 3;
  std_msgs::Header h;
  h.frame_id = "odom";
  EXPECT_EQ(toStatusMsg(step, h, 0, 0.0)->epoch, 3u);
  const TrackingEventPtr e = toEventMsg(TrackingEvent::NEW_MAP, 3, "reinitialized", h);
  EXPECT_EQ(e->kind, "new_map");
  EXPECT_EQ(e->epoch, 3u);
  EXPECT_EQ(e->cause, "reinitialized");
  EXPECT_EQ(e->header.frame_id, "odom");
  EXPECT_EQ(toEventMsg(TrackingEvent::TIME_RESET, 3, "time_reset", h)->kind, "time_reset");
}

TEST(TrackingConversion, AnUnknownTwistIsNotFilled) {
  OdometrySample s;  // has_twist = false: the first pose of a map
  s.twist_covariance = Matrix6d::Identity();
  const nav_msgs::OdometryPtr o = toOdometryMsg(s, std_msgs::Header(), "base_link");
  for (double v : o->twist.covariance) EXPECT_EQ(v, 0.0) << "no -1 marker: nav_msgs has none";
  EXPECT_EQ(o->twist.twist.linear.x, 0.0);
  EXPECT_EQ(o->pose.covariance[0], 1.0);
}
