// iraf_vo_simulate: renders a textured room along a smooth 6-DoF loop through a pinhole-radtan or
// Kannala-Brandt camera, applies photometric events and writes an ASL folder (+ TUM ground truth,
// events.csv, optionally a rosbag with /cam0/image_raw mono8 and /groundtruth/pose).
//
//   iraf_vo_simulate --preset clean|dark|overexposed|flicker|mixed --out DIR [--frames N]
//       [--camera pinhole|fisheye|path/to/sensor.yaml] [--width W --height H] [--seed S] [--speed X]
//       [--supersample S] [--motion-blur K] [--bag OUT.bag] [--threads N] [--no-photos] [--depth]
//   iraf_vo_simulate --benchmark N [--camera ...]   (render speed, single core and all cores)
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

#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/renderer.h"
#include "iraf_vo/sim/scene.h"
#include "iraf_vo/sim/sequence.h"

namespace {

void usage(std::ostream& os) {
  os << "usage: iraf_vo_simulate --preset " << iraf_vo::photometricPresetNames() << " --out DIR\n"
        "         [--frames N (400 = 20 s at 20 Hz)] [--camera pinhole|fisheye|path/to/sensor.yaml]\n"
        "         [--width W --height H] [--seed S] [--speed X (loop rate, 1 = one loop in 20 s)]\n"
        "         [--supersample S (1..4)] [--motion-blur K (sub-frame renders)] [--exposure SEC]\n"
        "         [--bag OUT.bag] [--threads N (0 = all cores)] [--no-photos]\n"
        "         [--depth (also OUT/mav0/depth0: 16-bit PNG z-depth in mm)]\n"
        "       iraf_vo_simulate --benchmark N [--camera ...] [--width W --height H]\n";
}

bool parseInt(const std::string& key, const std::string& v, int lo, int hi, int* out) {
  try {
    size_t used = 0;
    const long x = std::stol(v, &used);
    if (used != v.size() || x < lo || x > hi) throw std::out_of_range("range");
    *out = static_cast<int>(x);
    return true;
  } catch (const std::exception&) {
    std::cerr << "iraf_vo_simulate: " << key << " must be an integer in [" << lo << ", " << hi << "] (got '" << v << "')\n";
    return false;
  }
}

bool parseDouble(const std::string& key, const std::string& v, double lo, double hi, double* out) {
  try {
    size_t used = 0;
    const double x = std::stod(v, &used);
    if (used != v.size() || !(x >= lo && x <= hi)) throw std::out_of_range("range");
    *out = x;
    return true;
  } catch (const std::exception&) {
    std::cerr << "iraf_vo_simulate: " << key << " must be a number in [" << lo << ", " << hi << "] (got '" << v << "')\n";
    return false;
  }
}

}  // namespace

int main(int argc, char** argv) {
  iraf_vo::SimParams sim;
  iraf_vo::TrajectoryParams traj;
  iraf_vo::SceneParams scene_params;
  std::string preset, out_dir, bag_path;
  int seed = 1, benchmark = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(std::cout);
      return 0;
    }
    if (a == "--no-photos") {
      scene_params.photo_dir.clear();
      continue;
    }
    if (a == "--depth") {
      sim.write_depth = true;
      continue;
    }
    if (i + 1 >= argc) {
      std::cerr << "iraf_vo_simulate: " << a << " needs a value\n";
      usage(std::cerr);
      return 2;
    }
    const std::string v = argv[++i];
    bool ok = true;
    if (a == "--preset") preset = v;
    else if (a == "--out") out_dir = v;
    else if (a == "--bag") bag_path = v;
    else if (a == "--camera") sim.camera = v;
    else if (a == "--frames") ok = parseInt(a, v, 1, 1000000, &sim.frames);
    else if (a == "--width") ok = parseInt(a, v, 16, 8192, &sim.width);
    else if (a == "--height") ok = parseInt(a, v, 16, 8192, &sim.height);
    else if (a == "--seed") ok = parseInt(a, v, 0, 2147483647, &seed);
    else if (a == "--threads") ok = parseInt(a, v, 0, 256, &sim.threads);
    else if (a == "--supersample") ok = parseInt(a, v, 1, 4, &sim.supersample);
    else if (a == "--motion-blur") ok = parseInt(a, v, 1, 64, &sim.motion_blur_samples);
    else if (a == "--exposure") ok = parseDouble(a, v, 0.0, 0.05, &sim.exposure_time_s);
    else if (a == "--speed") ok = parseDouble(a, v, 0.05, 5.0, &traj.speed);
    else if (a == "--benchmark") ok = parseInt(a, v, 1, 100000, &benchmark);
    else {
      std::cerr << "iraf_vo_simulate: unknown argument '" << a << "'\n";
      usage(std::cerr);
      return 2;
    }
    if (!ok) return 2;
  }
  if (benchmark == 0 && (preset.empty() || out_dir.empty())) {
    std::cerr << "iraf_vo_simulate: --preset and --out are required\n";
    usage(std::cerr);
    return 2;
  }
  sim.seed = static_cast<uint64_t>(seed);
  scene_params.seed = sim.seed;
  iraf_vo::PhotometricParams photometric;
  if (benchmark == 0 && !iraf_vo::photometricPreset(preset, sim.frames, false, sim.seed, &photometric)) {
    std::cerr << "iraf_vo_simulate: unknown --preset '" << preset << "' (use " << iraf_vo::photometricPresetNames() << ")\n";
    return 2;
  }

  std::string err;
  iraf_vo::CameraModelPtr camera = iraf_vo::makeSimCamera(sim.camera, sim.width, sim.height, &err);
  if (!camera) {
    std::cerr << "iraf_vo_simulate: " << err << "\n";
    return 2;
  }
  if (sim.threads > 0) cv::setNumThreads(sim.threads);

  auto t0 = std::chrono::steady_clock::now();
  std::shared_ptr<const iraf_vo::Scene> scene;
  std::unique_ptr<iraf_vo::Renderer> renderer;
  try {
    scene = std::make_shared<const iraf_vo::Scene>(iraf_vo::Scene::makeDefaultRoom(scene_params));
    renderer = std::make_unique<iraf_vo::Renderer>(camera, scene, sim);
  } catch (const std::exception& e) {
    std::cerr << "iraf_vo_simulate: " << e.what() << "\n";
    return 2;
  }
  const double setup_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
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
  auto on_frame = [&](const iraf_vo::SimFrame& f) {
    if (!bag) return;
    const ros::Time stamp(static_cast<uint32_t>(f.stamp_ns / 1000000000LL), static_cast<uint32_t>(f.stamp_ns % 1000000000LL));
    std_msgs::Header h;
    h.stamp = stamp;
    h.seq = static_cast<uint32_t>(f.index);
    h.frame_id = "cam0";
    bag->write("/cam0/image_raw", stamp, cv_bridge::CvImage(h, sensor_msgs::image_encodings::MONO8, f.image).toImageMsg());
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
    ok = iraf_vo::simulateSequence(*renderer, traj, photometric, out_dir, on_frame, &rep, &err);
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (bag) bag->close();
  if (!ok) {
    std::cerr << "iraf_vo_simulate: " << err << "\n";
    return 1;
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "wrote " << rep.frames << " frames (" << preset << ") to " << out_dir << (bag ? " and " + bag_path : "")
            << " in " << total << " s: render " << rep.render_ms / rep.frames << " ms/frame ("
            << 1000.0 * rep.frames / rep.render_ms << " frames/s), photometric " << rep.photometric_ms / rep.frames
            << " ms/frame, png " << rep.write_ms / rep.frames << " ms/frame\n";
  return 0;
}
