// rostest: values the dynamic_reconfigure server of a nodelet wrote back to the parameter server are not "given by
// the user" in a later run on the same roscore, so a TUM-VI tracker after a EuRoC one gets the TUM-VI resolution
// rule (search radii, initialization thresholds, parallax); a field the user does give is kept.
#include <gtest/gtest.h>

#include <nodelet/loader.h>
#include <ros/ros.h>

#include <string>

#include "common/wait_for.h"
#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/pipeline/pipeline_params.h"
#include "iraf_vo/tracking/tracker_params.h"

using namespace iraf_vo;
using iraf_vo::test::waitFor;

namespace {

const std::string kConfig = std::string(IRAF_VO_SOURCE_DIR) + "/config/";

/// The tracker parameters the rule gives for a camera file, starting from the defaults.
TrackerParams expectedFor(const std::string& camera_file, const std::set<std::string>& user_set,
                          const TrackerParams& start = TrackerParams()) {
  std::string err;
  const CameraModelPtr cam = loadCamera(camera_file, &err);
  EXPECT_TRUE(cam) << err;
  TrackerParams p = start;
  applyTrackerResolutionRule(cam->width(), cam->height(), cam->focal(), cam->modelName() == "kannala-brandt",
                             user_set, &p);
  return p;
}

std::string g_mismatch;  // the last field serverShows() found different

/// The rule's fields on the parameter server (written back by the tracker's dynamic_reconfigure server) equal p.
bool serverShows(const TrackerParams& p) {
  const ParamTable<TrackerParams>& table = trackerParamTable();
  for (const char* name : {"search_radius_px", "search_radius_wide_px", "search_radius_refine_px", "init_min_matches",
                           "init_min_triangulated", "init_min_parallax_points", "min_triangulation_parallax_deg"}) {
    XmlRpc::XmlRpcValue v;
    if (!ros::param::get(std::string("/tracker/") + name, v)) return (g_mismatch = std::string(name) + " not set"), false;
    TrackerParams q = p;
    std::string text = v.getType() == XmlRpc::XmlRpcValue::TypeDouble ? formatDouble(static_cast<double>(v))
                       : v.getType() == XmlRpc::XmlRpcValue::TypeInt ? std::to_string(static_cast<int>(v))
                                                                      : std::string();
    std::string err;
    if (!table.set(&q, name, text, &err) || table.get(q, *table.find(name)) != table.get(p, *table.find(name)))
      return (g_mismatch = std::string(name) + " is " + text + ", expected " + table.get(p, *table.find(name))), false;
  }
  return true;
}

void load(nodelet::Loader& loader) {
  ASSERT_TRUE(loader.load("/tracker", "iraf_vo/TrackerNodelet", ros::M_string(), nodelet::V_string()));
}

}  // namespace

TEST(Relaunch, ASecondRunGetsItsOwnCamerasResolutionRule) {
  const TrackerParams euroc = expectedFor(kConfig + "euroc_cam0.yaml", {});
  const TrackerParams tumvi = expectedFor(kConfig + "tumvi_cam0.yaml", {});
  ASSERT_NE(euroc.search_radius_px, tumvi.search_radius_px) << "the two cameras must differ for this test";

  nodelet::Loader loader(false);
  ros::param::set("/tracker/camera_file", kConfig + "euroc_cam0.yaml");
  ros::param::set("/tracker/mapping_thread", false);
  load(loader);
  ASSERT_TRUE(waitFor([&] { return serverShows(euroc); }, 20.0)) << "first run: EuRoC's rule not on the server: " << g_mismatch;
  ASSERT_TRUE(loader.unload("/tracker"));

  // Second run, same roscore: the server's write-backs of the first run are still there.
  ros::param::set("/tracker/camera_file", kConfig + "tumvi_cam0.yaml");
  load(loader);
  EXPECT_TRUE(waitFor([&] { return serverShows(tumvi); }, 20.0))
      << "second run kept the first run's search radii (" << euroc.search_radius_px << " px) instead of TUM-VI's ("
      << tumvi.search_radius_px << " px): " << g_mismatch;
  ASSERT_TRUE(loader.unload("/tracker"));

  // Third run: a field the user gives now is kept, the rest follows the camera.
  ros::param::set("/tracker/camera_file", kConfig + "euroc_cam0.yaml");
  ros::param::set("/tracker/search_radius_px", 17.0);
  TrackerParams given = euroc;
  given.search_radius_px = 17.0;
  load(loader);
  EXPECT_TRUE(waitFor([&] { return serverShows(given); }, 20.0)) << "the user's search_radius_px 17 was not kept: " << g_mismatch;
  ASSERT_TRUE(loader.unload("/tracker"));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "relaunch_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
