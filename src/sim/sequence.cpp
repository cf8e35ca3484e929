#include "iraf_vo/sim/sequence.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <opencv2/imgcodecs.hpp>  // IMREAD_* flags
#include <opencv2/imgproc.hpp>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/common/error_out.h"
#include "iraf_vo/common/wall_clock.h"
#include "iraf_vo/sim/image_formation.h"
#include "iraf_vo/io/image_codecs.h"

namespace iraf_vo {

namespace fs = std::filesystem;

CameraModelPtr makeSimCamera(const std::string& camera, int width, int height, std::string* error) {
  std::vector<double> p;
  std::string model;
  int w0, h0;
  if (camera == "pinhole") {
    // EuRoC cam0: fu fv cu cv, radtan k1 k2 p1 p2.
    model = "pinhole-radtan", w0 = 752, h0 = 480;
    p = {458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  } else if (camera == "kitti") {
    // KITTI odometry cam0 (rectified grayscale, 1241x376): no distortion.
    model = "pinhole-radtan", w0 = 1241, h0 = 376;
    p = {718.856, 718.856, 607.1928, 185.2157, 0.0, 0.0, 0.0, 0.0};
  } else if (camera == "davis240") {
    // DAVIS240-like 240x180 sensor with a ~62 deg lens and mild barrel distortion.
    model = "pinhole-radtan", w0 = 240, h0 = 180;
    p = {200.0, 200.0, 119.5, 89.5, -0.1, 0.02, 0.0, 0.0};
  } else if (camera == "fisheye") {
    // TUM-VI cam0 512x512, equidistant (Kannala-Brandt) k1..k4.
    model = "kannala-brandt", w0 = 512, h0 = 512;
    p = {190.978, 190.973, 254.932, 256.897, 0.0034824, 0.00071503, -0.0020532, 0.00020294};
  } else {
    std::string err;
    CameraModelPtr cam = loadCamera(camera, &err);
    if (!cam) {
      setError(error, "camera '" + camera + "': " + err);
      return nullptr;
    }
    if ((width > 0 && width != cam->width()) || (height > 0 && height != cam->height())) {
      setError(error, "camera '" + camera + "' is " + std::to_string(cam->width()) + "x" + std::to_string(cam->height()) +
                          ": --width/--height can only rescale the built-in pinhole/fisheye cameras");
      return nullptr;
    }
    return cam;
  }
  const int w = width > 0 ? width : w0, h = height > 0 ? height : h0;
  const double sx = static_cast<double>(w) / w0, sy = static_cast<double>(h) / h0;
  p[0] *= sx, p[2] = (p[2] + 0.5) * sx - 0.5;
  p[1] *= sy, p[3] = (p[3] + 0.5) * sy - 0.5;
  std::string err;
  CameraModelPtr cam = makeCamera(model, w, h, p, &err);
  if (!cam) setError(error, "camera '" + camera + "': " + err);
  return cam;
}

bool writeSensorYaml(const CameraModel& camera, double rate_hz, const std::string& path, std::string* error,
                     const Eigen::Isometry3d& T_BS) {
  const std::vector<double> p = camera.parameters();
  std::ofstream f(path);
  if (!f) {
    setError(error, path + ": cannot write");
    return false;
  }
  char buf[64];
  auto num = [&](double v) {
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return std::string(buf);
  };
  f << "# Written by iraf_vo_simulate (" << camera.modelName() << "). EuRoC/Kalibr layout.\n"
    << "sensor_type: camera\ncomment: iraf_vo simulated camera\n\n"
    << "T_BS:\n  cols: 4\n  rows: 4\n  data: [";
  const Eigen::Matrix4d M = T_BS.matrix();
  for (int i = 0; i < 16; ++i) {
    const double v = M(i / 4, i % 4);
    f << (v == 0.0 ? std::string("0.0") : v == 1.0 ? std::string("1.0") : num(v));
    f << (i == 15 ? "]\n\n" : i % 4 == 3 ? ",\n         " : ", ");
  }
  f << "rate_hz: " << num(rate_hz) << "\n"
    << "resolution: [" << camera.width() << ", " << camera.height() << "]\n"
    << "camera_model: pinhole\n"
    << "intrinsics: [" << num(p[0]) << ", " << num(p[1]) << ", " << num(p[2]) << ", " << num(p[3]) << "]  # fu, fv, cu, cv\n"
    << "distortion_model: " << camera.distortionModel() << "\n"
    << "distortion_coefficients: [";
  for (size_t i = 4; i < p.size(); ++i) f << (i > 4 ? ", " : "") << num(p[i]);
  f << "]\n";
  if (!f) {
    setError(error, path + ": write failed");
    return false;
  }
  return true;
}

std::string nsToSecondsString(int64_t ns) {
  const bool neg = ns < 0;
  const uint64_t a = neg ? static_cast<uint64_t>(-ns) : static_cast<uint64_t>(ns);
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%s%llu.%09llu", neg ? "-" : "", static_cast<unsigned long long>(a / 1000000000ULL),
                static_cast<unsigned long long>(a % 1000000000ULL));
  return buf;
}

std::string tumLine(int64_t stamp_ns, const Eigen::Isometry3d& T_W_C) {
  const Eigen::Quaterniond q(T_W_C.linear());
  const Eigen::Vector3d t = T_W_C.translation();
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s %.9f %.9f %.9f %.9f %.9f %.9f %.9f", nsToSecondsString(stamp_ns).c_str(), t.x(),
                t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  return buf;
}

bool makeDirs(const std::string& path, std::string* error) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec || !fs::is_directory(path)) {
    setError(error, path + ": cannot create directory" + (ec ? " (" + ec.message() + ")" : std::string()));
    return false;
  }
  return true;
}

namespace {
/// Renders (with depth when asked) and forms the image of frame f->index, adding to the report's times.
using FormFrame = std::function<void(SimFrame* f, SimulateReport* rep)>;

bool writeSimulation(const Renderer& renderer, const Renderer* right, const TrajectoryParams& traj,
                     const PhotometricParams& photometric, const FormFrame& form, const std::string& out_dir,
                     const std::function<void(const SimFrame&)>& on_frame, SimulateReport* report, std::string* error) {
  const int n = renderer.params().frames;
  const bool write_depth = renderer.params().write_depth;
  std::ofstream csv, gt, depth_csv, right_csv;
  const std::string depth_dir = out_dir + "/mav0/depth0";
  const std::string cam_dir = out_dir + "/mav0/cam0", right_dir = out_dir + "/mav0/cam1";
  if (!out_dir.empty()) {
    if (!makeDirs(cam_dir + "/data", error)) return false;
    if (!writeSensorYaml(renderer.camera(), renderer.params().rate_hz, cam_dir + "/sensor.yaml", error)) return false;
    if (right) {
      if (!makeDirs(right_dir + "/data", error)) return false;
      if (!writeSensorYaml(right->camera(), renderer.params().rate_hz, right_dir + "/sensor.yaml", error,
                           right->poseInRig()))
        return false;
      right_csv.open(right_dir + "/data.csv");
      if (!right_csv) {
        setError(error, right_dir + "/data.csv: cannot write");
        return false;
      }
      right_csv << "#timestamp [ns],filename\n";
    }
    if (!writeEventsCsv(out_dir + "/events.csv", photometric, n, error)) return false;
    csv.open(cam_dir + "/data.csv");
    gt.open(out_dir + "/groundtruth.txt");
    if (!csv || !gt) {
      setError(error, out_dir + ": cannot write data.csv / groundtruth.txt");
      return false;
    }
    csv << "#timestamp [ns],filename\n";
    if (write_depth) {
      if (!makeDirs(depth_dir + "/data", error)) return false;
      depth_csv.open(depth_dir + "/data.csv");
      if (!depth_csv) {
        setError(error, depth_dir + "/data.csv: cannot write");
        return false;
      }
      depth_csv << "#timestamp [ns],filename (16-bit PNG, z-depth in mm, 0 = no hit)\n";
    }
    gt << "# iraf_vo_simulate ground truth: pose of the camera in the world (T_W_C), TUM format\n"
       << "# timestamp[s] tx ty tz qx qy qz qw\n";
  }
  SimulateReport rep;
  for (int i = 0; i < n; ++i) {
    SimFrame f;
    f.index = i;
    f.stamp_ns = renderer.frameStampNs(i);
    f.T_W_C = trajectoryPose(traj, renderer.frameTime(i));
    form(&f, &rep);
    auto t0 = SteadyClock::now();
    if (!out_dir.empty()) {
      t0 = SteadyClock::now();
      const std::string name = std::to_string(f.stamp_ns) + ".png";
      if (!codecs::imwrite(cam_dir + "/data/" + name, f.image)) {
        setError(error, cam_dir + "/data/" + name + ": cannot write PNG");
        return false;
      }
      csv << f.stamp_ns << ',' << name << '\n';
      if (right) {
        if (!codecs::imwrite(right_dir + "/data/" + name, f.right_image)) {
          setError(error, right_dir + "/data/" + name + ": cannot write PNG");
          return false;
        }
        right_csv << f.stamp_ns << ',' << name << '\n';
      }
      if (write_depth) {
        cv::Mat mm;
        f.depth.convertTo(mm, CV_16U, 1000.0);  // saturates at 65.535 m
        if (!codecs::imwrite(depth_dir + "/data/" + name, mm)) {
          setError(error, depth_dir + "/data/" + name + ": cannot write PNG");
          return false;
        }
        depth_csv << f.stamp_ns << ',' << name << '\n';
      }
      gt << tumLine(f.stamp_ns, f.T_W_C) << '\n';
      rep.write_ms += msSince(t0);
    }
    if (on_frame) on_frame(f);
    ++rep.frames;
  }
  if (!out_dir.empty() && (!csv.flush() || !gt.flush() || (right && !right_csv.flush()))) {
    setError(error, out_dir + ": write failed (disk full?)");
    return false;
  }
  if (report) *report = rep;
  return true;
}
}  // namespace

bool simulateSequence(const Renderer& renderer, const TrajectoryParams& traj, const PhotometricParams& photometric,
                      const std::string& out_dir, const std::function<void(const SimFrame&)>& on_frame,
                      SimulateReport* report, std::string* error) {
  const std::string perr = validate(photometric);
  if (!perr.empty()) {
    setError(error, "photometric events: " + perr);
    return false;
  }
  cv::Mat radiance;
  const bool write_depth = renderer.params().write_depth;
  auto form = [&](SimFrame* f, SimulateReport* rep) {
    auto t0 = SteadyClock::now();
    renderer.renderFrame(traj, f->index, &radiance, write_depth ? &f->depth : nullptr);
    rep->render_ms += msSince(t0);
    t0 = SteadyClock::now();
    applyPhotometric(radiance, f->index, photometric, &f->image);
    rep->photometric_ms += msSince(t0);
  };
  return writeSimulation(renderer, nullptr, traj, photometric, form, out_dir, on_frame, report, error);
}

bool simulateSequence(const Renderer& renderer, const TrajectoryParams& traj, const LightProfile& light,
                      const std::string& out_dir, const std::function<void(const SimFrame&)>& on_frame,
                      SimulateReport* report, std::string* error) {
  return simulateSequence(renderer, nullptr, traj, light, out_dir, on_frame, report, error);
}

bool simulateSequence(const Renderer& renderer, const Renderer* right, const TrajectoryParams& traj,
                      const LightProfile& light, const std::string& out_dir,
                      const std::function<void(const SimFrame&)>& on_frame, SimulateReport* report,
                      std::string* error) {
  const std::string lerr = validate(light);
  if (!lerr.empty()) {
    setError(error, "light profile '" + light.name + "': " + lerr);
    return false;
  }
  if (right && (right->params().frames != renderer.params().frames ||
                right->params().rate_hz != renderer.params().rate_hz)) {
    setError(error, "stereo: the right camera's frames and rate must be the left's");
    return false;
  }
  ImageFormation formation(light, renderer.cameraPtr());
  // The right camera: the left's exposure and gain, its own sensor noise (noise stream 1).
  std::unique_ptr<ImageFormation> right_formation;
  if (right) right_formation = std::make_unique<ImageFormation>(light, right->cameraPtr(), 1);
  const int n = renderer.params().frames;
  const Eigen::Vector2d centre(0.5 * (renderer.camera().width() - 1), 0.5 * (renderer.camera().height() - 1));
  if (light.glare.enabled) {
    std::vector<Eigen::Vector3d> lamps;
    for (int k = 0; k < light.glare.spots; ++k) {
      const int frame = static_cast<int>((k + 0.5) * n / light.glare.spots);
      Eigen::Vector3d p;
      if (renderer.castPixel(trajectoryPose(traj, renderer.frameTime(frame)), centre, &p)) lamps.push_back(p);
    }
    formation.setGlareLamps(lamps);
    if (right_formation) right_formation->setGlareLamps(lamps);
  }
  const bool geometry = formation.needsGeometry() || renderer.params().write_depth;
  std::vector<FrameLight> lights;
  cv::Mat radiance;
  FrameGeometry g;
  auto form = [&](SimFrame* f, SimulateReport* rep) {
    auto t0 = SteadyClock::now();
    if (f->index == 0 && light.ae.enabled) {  // a camera that has been running: its auto-exposure has settled on the first view
      renderer.renderFrame(traj, 0, formation.nextExposure().time_s, &radiance, geometry ? &g.depth : nullptr);
      g.T_W_C = f->T_W_C;
      formation.settle(radiance, geometry ? &g : nullptr);
    }
    renderer.renderFrame(traj, f->index, formation.nextExposure().time_s, &radiance, geometry ? &g.depth : nullptr);
    g.T_W_C = f->T_W_C;
    rep->render_ms += msSince(t0);
    t0 = SteadyClock::now();
    formation.capture(f->index, radiance, geometry ? &g : nullptr, &f->image, &f->light);
    if (geometry) f->depth = g.depth.clone();
    lights.push_back(f->light);
    rep->photometric_ms += msSince(t0);
    if (!right) return;
    t0 = SteadyClock::now();
    FrameGeometry gr;
    right->renderFrame(traj, f->index, f->light.exposure.time_s, &radiance, geometry ? &gr.depth : nullptr);
    gr.T_W_C = right->cameraPose(traj, right->frameTime(f->index));
    rep->render_ms += msSince(t0);
    t0 = SteadyClock::now();
    right_formation->captureWithExposure(f->index, f->light.exposure, radiance, geometry ? &gr : nullptr,
                                         &f->right_image, &f->right_light);
    rep->photometric_ms += msSince(t0);
  };
  if (!writeSimulation(renderer, right, traj, light.scene, form, out_dir, on_frame, report, error)) return false;
  return out_dir.empty() || writeExposureCsv(out_dir + "/exposure.csv", lights, error);
}

bool readAslCsv(const std::string& path, std::vector<std::pair<int64_t, std::string>>* rows, std::string* error) {
  std::ifstream f(path);
  if (!f) {
    setError(error, path + ": cannot open");
    return false;
  }
  rows->clear();
  std::string line;
  int lineno = 0;
  while (std::getline(f, line)) {
    ++lineno;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const size_t comma = line.find(',');
    std::string name = comma == std::string::npos ? std::string() : line.substr(comma + 1);
    name.erase(0, name.find_first_not_of(' '));
    try {
      size_t used = 0;
      const long long ts = std::stoll(line.substr(0, comma), &used);
      if (name.empty()) throw std::invalid_argument("no file name");
      rows->emplace_back(ts, name);
    } catch (const std::exception&) {
      std::cerr << path << ":" << lineno << ": bad row '" << line << "' (expected 'timestamp_ns,filename'), skipped\n";
    }
  }
  return true;
}

}  // namespace iraf_vo
