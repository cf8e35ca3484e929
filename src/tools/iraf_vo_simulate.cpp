// iraf_vo_simulate: renders a textured scene (room, street or slider table) along the trajectory of a
// motion preset (room loop, drive, slider, handheld_fast; optionally standing still first) through a
// pinhole-radtan or Kannala-Brandt camera, forms the images with a light profile (scene light, sensor
// noise, auto-exposure; the shutter's motion blur follows the exposure) and writes an ASL folder (+ TUM
// ground truth, events.csv, exposure.csv, optionally a rosbag with /cam0/image_raw mono8 and /groundtruth/pose).
// --stereo adds the right camera of a rig (mav0/cam1, /cam1/image_raw): same intrinsics, the camera's
// baseline along x (--baseline), optionally a small rotation (--rig-yaw/--rig-pitch/--rig-roll).
//
//   iraf_vo_simulate --preset clean|dark|overexposed|flicker|mixed|night|ae_hunting|light_switch|blackout|
//                             flashlight|glare --out DIR [--motion M] [--static-start SEC]
//       [--frames N] [--rate HZ] [--camera pinhole|fisheye|kitti|davis240|path/to/sensor.yaml]
//       [--width W --height H] [--seed S] [--speed X] [--supersample S] [--motion-blur K] [--exposure SEC]
//       [--bag OUT.bag] [--threads N] [--no-photos] [--depth]
//       [--stereo [--baseline M] [--rig-yaw DEG] [--rig-pitch DEG] [--rig-roll DEG]]
//   iraf_vo_simulate --benchmark N [--camera ...]   (render speed, single core and all cores)
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include <opencv2/core/utility.hpp>

#include <cv_bridge/cv_bridge.h>
#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include "iraf_vo/pipeline/command_line.h"
#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/motion_preset.h"
#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/renderer.h"
#include "iraf_vo/sim/scene.h"
#include "iraf_vo/sim/scene_presets.h"
#include "iraf_vo/sim/sequence.h"
#include "iraf_vo/sim/sim_stereo_rig.h"

int main(int argc, char** argv) {
  iraf_vo::SimParams sim;
  iraf_vo::TrajectoryParams traj;
  iraf_vo::SceneParams scene_params;
  std::string preset, out_dir, bag_path, motion_name = "room";
  int seed = 1, benchmark = 0;
  double static_start = 0.0;
  double blackout_s = 0.0;  // 0: the preset's
  bool no_photos = false, stereo = false;
  iraf_vo::SimStereoRig rig;
  iraf_vo::CommandLine cli(
      "iraf_vo_simulate",
      "Renders a textured scene along a motion preset and writes an ASL folder (+ TUM ground truth, events.csv).\n"
      "       iraf_vo_simulate --benchmark N [--motion M] [--camera ...] [--width W --height H]\n"
      "Motions (each with its own default camera, rate, frames, motion blur; the options override them):\n"
      "  room           textured 8x6x3 m room, smooth 6-DoF loop, pinhole (EuRoC cam0 752x480), 20 Hz, 400 frames\n"
      "  drive          street (asphalt, facades 3-50 m, cars, trees), 10 m/s with gentle S-curves, camera 1.65 m\n"
      "                 high; kitti (1241x376, f 718.9), 10 Hz (1 m/frame), 100 frames, blur 3 x 2 ms\n"
      "  slider         pure sideways translation (0.25 m/s, 1 m travel, back and forth) past table objects at\n"
      "                 0.3-1 m and a wall at 4 m; davis240 (240x180, f 200, k1 -0.1), 25 Hz, 100 frames, blur 3 x 10 ms\n"
      "  handheld_fast  the room loop with fast hand rotations (<= 3 deg/frame); pinhole or --camera fisheye,\n"
      "                 20 Hz, 300 frames, motion blur 4 x 8 ms\n"
      "  highway        open road (low-contrast surface, posts and signs 8-10 m out, trees, woods 40-90 m, buildings\n"
      "                 90-220 m), 10 m/s with wide curves; kitti, 10 Hz (1 m/frame), 100 frames, blur 3 x 2 ms");
  cli.option("--preset", "P", &preset, "light profile: " + iraf_vo::lightProfileNames());
  cli.option("--out", "DIR", &out_dir, "output ASL folder");
  cli.option("--blackout-seconds", "SEC", &blackout_s, 0.05, 3600.0,
             "--preset blackout: the length of the darkness (default 1 s, at most 30 % of the frames)");
  cli.option("--motion", "M", &motion_name, iraf_vo::motionKindNames() + " (default room)");
  cli.option("--static-start", "SEC", &static_start, 0.0, 3600.0,
             "the camera stands still for SEC s, then accelerates over 1 s (any motion)");
  cli.option("--frames", "N", &sim.frames, 1, 1000000, "frames (default: the motion's)");
  cli.option("--rate", "HZ", &sim.rate_hz, 0.1, 1000.0, "frame rate (default: the motion's)");
  cli.option("--camera", "C", &sim.camera, "pinhole | fisheye | kitti | davis240 | path/to/sensor.yaml");
  cli.option("--width", "W", &sim.width, 16, 8192, "image width (with --height)");
  cli.option("--height", "H", &sim.height, 16, 8192, "image height (with --width)");
  cli.option("--seed", "S", &seed, 0, 2147483647, "random seed (default 1)");
  cli.option("--speed", "X", &traj.speed, 0.05, 5.0, "speed factor: loop rate, drive / slider speed");
  cli.option("--supersample", "S", &sim.supersample, 1, 4, "supersampling per side");
  cli.option("--motion-blur", "K", &sim.motion_blur_samples, 1, 64, "sub-frame renders");
  cli.option("--exposure", "SEC", &sim.exposure_time_s, 0.0, 0.05, "exposure time of the motion blur");
  cli.option("--bag", "OUT.bag", &bag_path, "also a rosbag with /cam0/image_raw mono8 and /groundtruth/pose");
  cli.option("--threads", "N", &sim.threads, 0, 256, "render threads (0 = all cores)");
  cli.flag("--no-photos", &no_photos, "no photo posters on the walls");
  cli.flag("--depth", &sim.write_depth, "also OUT/mav0/depth0: 16-bit PNG z-depth in mm");
  cli.flag("--stereo", &stereo, "also the right camera of a stereo rig: OUT/mav0/cam1 (+ /cam1/image_raw in the bag)");
  cli.option("--baseline", "M", &rig.baseline_m, 0.001, 5.0,
             "stereo baseline (default: the camera's rig: pinhole 0.110, fisheye 0.101, kitti 0.54, others 0.10)");
  cli.option("--rig-yaw", "DEG", &rig.yaw_deg, -10.0, 10.0, "stereo: right camera turned about y (toe-in)");
  cli.option("--rig-pitch", "DEG", &rig.pitch_deg, -10.0, 10.0, "stereo: right camera turned about x");
  cli.option("--rig-roll", "DEG", &rig.roll_deg, -10.0, 10.0, "stereo: right camera turned about z");
  cli.option("--benchmark", "N", &benchmark, 1, 100000, "render speed over N frames, single core and all cores");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  if (no_photos) scene_params.photo_dir.clear();
  const bool set_camera = cli.given("--camera"), set_frames = cli.given("--frames"), set_rate = cli.given("--rate"),
             set_blur = cli.given("--motion-blur"), set_exposure = cli.given("--exposure");
  if (!stereo && (cli.given("--baseline") || cli.given("--rig-yaw") || cli.given("--rig-pitch") ||
                  cli.given("--rig-roll"))) {
    std::cerr << "iraf_vo_simulate: --baseline and --rig-* need --stereo\n";
    return 2;
  }
  if (benchmark == 0 && (preset.empty() || out_dir.empty())) {
    std::cerr << "iraf_vo_simulate: --preset and --out are required\n" << cli.usage();
    return 2;
  }
  iraf_vo::MotionKind motion;
  if (!iraf_vo::parseMotionKind(motion_name, &motion)) {
    std::cerr << "iraf_vo_simulate: unknown --motion '" << motion_name << "' (use " << iraf_vo::motionKindNames() << ")\n";
    return 2;
  }
  // The motion's defaults, then the options given on the command line.
  const iraf_vo::MotionPreset mp = iraf_vo::motionPreset(motion);
  const double speed = traj.speed;
  traj = mp.traj;
  traj.speed = speed;  // loop rate (room, handheld_fast); the drive and slider speeds scale with it too
  traj.drive_speed_mps *= speed;
  traj.slider_speed_mps *= speed;
  traj.static_start_s = static_start;
  if (!set_camera) sim.camera = mp.camera;
  if (!set_frames) sim.frames = mp.frames;
  if (!set_rate) sim.rate_hz = mp.rate_hz;
  if (!set_blur) sim.motion_blur_samples = mp.motion_blur_samples;
  if (!set_exposure) sim.exposure_time_s = mp.exposure_time_s;
  scene_params.texels_per_m = mp.texels_per_m;
  sim.brightness = mp.brightness;
  const std::string terr = iraf_vo::validate(traj);
  if (!terr.empty()) {
    std::cerr << "iraf_vo_simulate: trajectory: " << terr << "\n";
    return 2;
  }
  sim.seed = static_cast<uint64_t>(seed);
  scene_params.seed = sim.seed;
  iraf_vo::LightProfile light;
  if (benchmark == 0 && !iraf_vo::lightProfile(preset, sim.frames, sim.rate_hz, sim.exposure_time_s, false, sim.seed,
                                               &light)) {
    std::cerr << "iraf_vo_simulate: unknown --preset '" << preset << "' (use " << iraf_vo::lightProfileNames() << ")\n";
    return 2;
  }
  if (blackout_s > 0.0 && preset != "blackout") {
    std::cerr << "iraf_vo_simulate: --blackout-seconds needs --preset blackout\n";
    return 2;
  }
  if (blackout_s > 0.0)
    for (iraf_vo::PhotometricEvent& e : light.scene.events)
      if (e.type == iraf_vo::PhotometricEventType::kLightSwitch)
        e.end_frame = std::min(sim.frames, e.start_frame + std::max(1, static_cast<int>(std::lround(blackout_s * sim.rate_hz))));
  // The flashlight is the only light: the scene is rendered as albedo (all ambient), the cone lights it.
  if (light.flashlight.enabled) scene_params.ambient = 1.0;

  std::string err;
  iraf_vo::CameraModelPtr camera = iraf_vo::makeSimCamera(sim.camera, sim.width, sim.height, &err);
  if (!camera) {
    std::cerr << "iraf_vo_simulate: " << err << "\n";
    return 2;
  }
  if (sim.threads > 0) cv::setNumThreads(sim.threads);

  auto t0 = std::chrono::steady_clock::now();
  std::shared_ptr<const iraf_vo::Scene> scene;
  std::unique_ptr<iraf_vo::Renderer> renderer, right;
  try {
    scene = std::make_shared<const iraf_vo::Scene>(
        iraf_vo::makeMotionScene(scene_params, traj, (sim.frames - 1) / sim.rate_hz + sim.exposure_time_s));
    renderer = std::make_unique<iraf_vo::Renderer>(camera, scene, sim);
    if (stereo && benchmark == 0) {
      right = std::make_unique<iraf_vo::Renderer>(camera, scene, sim);
      right->setPoseInRig(iraf_vo::rightCameraInLeft(rig, sim.camera));
    }
  } catch (const std::exception& e) {
    std::cerr << "iraf_vo_simulate: " << e.what() << "\n";
    return 2;
  }
  const double setup_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "motion: " << iraf_vo::toString(motion) << " (static start " << static_start << " s), "
            << sim.frames << " frames at " << sim.rate_hz << " Hz, motion blur " << sim.motion_blur_samples << " x "
            << sim.exposure_time_s * 1e3 << " ms\n";
  if (right) {
    const Eigen::Isometry3d& T = right->poseInRig();
    std::cout << "stereo: right camera at (" << T.translation().transpose() << ") m in the left camera, turned "
              << Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI << " deg\n";
  }
  std::cout << "camera: " << camera->describe() << "\nscene: " << scene->boxes().size() << " boxes, "
            << scene->photoPosters() << " photo posters; setup (textures + bearings) " << setup_ms << " ms\n";

  if (benchmark > 0) {
    // Render speed only (no photometric events, no writing): single core, then all cores.
    cv::Mat img;
    for (int threads : {1, 0}) {
      iraf_vo::SimParams p = sim;
      p.threads = threads;
      iraf_vo::Renderer r(camera, scene, p);
      cv::setNumThreads(threads == 0 ? -1 : 1);
      r.renderFrame(traj, 0, &img);  // warm-up
      const auto b0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      for (int i = 0; i < benchmark; ++i) r.renderFrame(traj, i, &img);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - b0).count();
      const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
      // CPU time (all threads of the process) next to wall time: the machine may be shared.
      std::cout << "render " << camera->width() << "x" << camera->height() << " supersample " << sim.supersample
                << (threads == 1 ? ", 1 thread: " : ", all cores (" + std::to_string(cv::getNumThreads()) + " threads): ")
                << benchmark / s << " frames/s wall (" << 1000.0 * s / benchmark << " ms/frame), "
                << benchmark / cpu << " frames per CPU-second\n";
    }
    iraf_vo::PhotometricParams mixed;
    iraf_vo::photometricPreset("mixed", benchmark, false, 1, &mixed);
    cv::setNumThreads(1);
    const auto b0 = std::chrono::steady_clock::now();
    cv::Mat out;
    for (int i = 0; i < benchmark; ++i) iraf_vo::applyPhotometric(img, i, mixed, &out);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - b0).count();
    std::cout << "photometric events (mixed preset), 1 thread: " << 1000.0 * s / benchmark << " ms/frame\n";
    return 0;
  }

  std::unique_ptr<rosbag::Bag> bag;
  if (!bag_path.empty()) {
    try {
      bag = std::make_unique<rosbag::Bag>(bag_path, rosbag::bagmode::Write);
    } catch (const std::exception& e) {
      std::cerr << "iraf_vo_simulate: cannot open bag '" << bag_path << "': " << e.what() << "\n";
      return 1;
    }
  }
  // The camera's range over the sequence (exposure.csv has every frame).
  double t_min = 1e9, t_max = 0.0, g_max = 0.0, clip_max = 0.0, grey_min = 255.0;
  auto on_frame = [&](const iraf_vo::SimFrame& f) {
    t_min = std::min(t_min, f.light.exposure.time_s), t_max = std::max(t_max, f.light.exposure.time_s);
    g_max = std::max(g_max, f.light.exposure.gain), clip_max = std::max(clip_max, f.light.saturated);
    grey_min = std::min(grey_min, f.light.mean_grey);
    if (!bag) return;
    const ros::Time stamp(static_cast<uint32_t>(f.stamp_ns / 1000000000LL), static_cast<uint32_t>(f.stamp_ns % 1000000000LL));
    std_msgs::Header h;
    h.stamp = stamp;
    h.seq = static_cast<uint32_t>(f.index);
    h.frame_id = "cam0";
    bag->write("/cam0/image_raw", stamp, cv_bridge::CvImage(h, sensor_msgs::image_encodings::MONO8, f.image).toImageMsg());
    if (!f.right_image.empty()) {
      std_msgs::Header hr = h;
      hr.frame_id = "cam1";
      bag->write("/cam1/image_raw", stamp,
                 cv_bridge::CvImage(hr, sensor_msgs::image_encodings::MONO8, f.right_image).toImageMsg());
    }
    geometry_msgs::PoseStamped pose;
    pose.header = h;
    pose.header.frame_id = "world";
    const Eigen::Quaterniond q(f.T_W_C.linear());
    pose.pose.position.x = f.T_W_C.translation().x();
    pose.pose.position.y = f.T_W_C.translation().y();
    pose.pose.position.z = f.T_W_C.translation().z();
    pose.pose.orientation.x = q.x(), pose.pose.orientation.y = q.y(), pose.pose.orientation.z = q.z(),
    pose.pose.orientation.w = q.w();
    bag->write("/groundtruth/pose", stamp, pose);
  };
  iraf_vo::SimulateReport rep;
  t0 = std::chrono::steady_clock::now();
  bool ok = false;
  try {
    ok = iraf_vo::simulateSequence(*renderer, right.get(), traj, light, out_dir, on_frame, &rep, &err);
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (bag) bag->close();
  if (!ok) {
    std::cerr << "iraf_vo_simulate: " << err << "\n";
    return 1;
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "camera: exposure " << t_min * 1e3 << "-" << t_max * 1e3 << " ms, gain up to " << g_max
            << ", darkest frame mean grey " << grey_min << ", up to " << 100.0 * clip_max << " % of a frame clipped\n";
  std::cout << "wrote " << rep.frames << (right ? " stereo" : "") << " frames (" << preset << ") to " << out_dir << (bag ? " and " + bag_path : "")
            << " in " << total << " s: render " << rep.render_ms / rep.frames << " ms/frame ("
            << 1000.0 * rep.frames / rep.render_ms << " frames/s), photometric " << rep.photometric_ms / rep.frames
            << " ms/frame, png " << rep.write_ms / rep.frames << " ms/frame\n";
  return 0;
}
