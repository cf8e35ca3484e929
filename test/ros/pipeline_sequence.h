// The sequence the pipeline rostest plays (test/ros/pipeline.cpp): rendered once by main() with iraf_vo_simulate
// (`dark` preset) through test/ros/sim_cam0_376x240.yaml, the offline runner's trajectory on it as the reference,
// the frames in memory and the simulator's ground truth.
#pragma once

#include <ros/time.h>

#include <opencv2/core.hpp>

#include <cstdlib>
#include <string>
#include <vector>

#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/io/trajectory.h"

namespace iraf_vo_pipeline_test {

inline constexpr int kFrames = 240;
inline std::string g_sim_dir;  // set by main()
inline std::string g_sim_error;

struct Frame {
  ros::Time stamp;
  cv::Mat gray;
};
inline std::vector<Frame> g_frames;
inline iraf_vo::Trajectory g_gt;


/// Renders the sequence into a temp folder (g_sim_dir), runs iraf_vo_run on it (offline.txt) and loads the frames
/// and the ground truth. False with `error` set when a step fails.
inline bool renderSequence(std::string* error) {
  char tmpl[] = "/tmp/iraf_vo_pipeline_XXXXXX";
  if (!mkdtemp(tmpl)) return (*error = "mkdtemp failed"), false;
  g_sim_dir = tmpl;
  const std::string cmd = std::string(IRAF_VO_BIN_DIR) + "/iraf_vo_simulate --preset dark --frames " +
                          std::to_string(kFrames) + " --camera " + IRAF_VO_SOURCE_DIR +
                          "/test/ros/sim_cam0_376x240.yaml --out " + g_sim_dir + " > " + g_sim_dir + "/sim.log 2>&1";
  if (std::system(cmd.c_str()) != 0) return (*error = "failed: " + cmd), false;
  // The offline runner on the same frames with the launch's parameters (reference for the ATE).
  const std::string run = std::string(IRAF_VO_BIN_DIR) + "/iraf_vo_run --quiet --dataset " + g_sim_dir +
                          " --camera " + IRAF_VO_SOURCE_DIR + "/test/ros/sim_cam0_376x240.yaml --config " +
                          IRAF_VO_SOURCE_DIR + "/config/default.yaml --set features.n_features=600" +
                          " --set tracker.mapping_thread=false --out " + g_sim_dir + "/offline.txt > " + g_sim_dir +
                          "/run.log 2>&1";
  if (std::system(run.c_str()) != 0) return (*error = "failed: " + run), false;
  iraf_vo::AslImageReader reader;
  if (!reader.open(g_sim_dir, error)) return false;
  for (size_t i = 0; i < reader.entries().size(); ++i) {
    Frame f;
    if (!reader.loadImage(i, &f.gray, error)) return false;
    f.stamp.fromNSec(static_cast<uint64_t>(reader.entries()[i].stamp_ns));
    g_frames.push_back(f);
  }
  if (static_cast<int>(g_frames.size()) != kFrames) return (*error = "wrong frame count"), false;
  return iraf_vo::readTrajectory(g_sim_dir + "/groundtruth.txt", &g_gt, error);
}


}  // namespace iraf_vo_pipeline_test
