// Tracking results -> messages (src/ros/tracking_conversion.cpp): TrackingStatus.reason while initializing.
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
