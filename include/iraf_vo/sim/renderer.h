// Ray-casting renderer of the simulator (ROS-free). For every pixel the camera model unprojects the
// (distorted) pixel to a bearing once at construction; a frame then rotates the bearings into the
// world, intersects the scene analytically and samples the mipmapped textures with a level chosen
// from the pixel footprint (t * pixel angle / sqrt(cos incidence)). Optional s x s supersampling and
// motion blur (average of sub-frame renders within the exposure time).
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <memory>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/sim/scene.h"
#include "iraf_vo/sim/trajectory.h"

namespace iraf_vo {

struct SimParams {
  int frames = 400;          // 20 s at 20 Hz: one loop of the default trajectory
  double rate_hz = 20.0;
  int supersample = 1;       // s x s rays per pixel (1 = mipmapping only)
  int threads = 0;           // 0 = all cores (cv::parallel_for_), 1 = single core
  double brightness = 1.25;  // radiance -> 8-bit scale: pixel = 255 * brightness * radiance (before events)
  int motion_blur_samples = 1;   // > 1: average of this many sub-frame renders over the exposure
  double exposure_time_s = 0.01; // exposure window for motion blur (s)
  uint64_t seed = 1;         // textures, noise
  int64_t start_ns = 1000000000000000000LL;  // timestamp of frame 0 (ns) = 1e9 s
  std::string camera = "pinhole";  // pinhole | fisheye | path/to/sensor.yaml
  int width = 0, height = 0;       // 0 = the camera's own resolution
  bool span_renderer = true;       // supersample 1: vectorizable 16-pixel spans; false: reference per-ray path
  bool write_depth = false;        // simulateSequence: also OUT/mav0/depth0 (16-bit PNG, z-depth in mm)
};

/// Returns a message naming what is wrong, or "" when usable.
std::string validate(const SimParams& params);

class Renderer {
 public:
  /// Precomputes the bearings of every (sub)pixel. Throws std::invalid_argument for a null camera
  /// or bad params.
  Renderer(CameraModelPtr camera, std::shared_ptr<const Scene> scene, const SimParams& params);

  /// Renders radiance * 255 * brightness (CV_32FC1, unclipped) at pose T_W_C. `depth` (optional,
  /// CV_32FC1) receives the z-depth in the camera frame of the pixel-centre ray (0 where nothing was hit).
  void render(const Eigen::Isometry3d& T_W_C, cv::Mat* radiance, cv::Mat* depth = nullptr) const;

  /// Frame i of the trajectory (motion blur: average over the exposure window around its timestamp).
  void renderFrame(const TrajectoryParams& traj, int frame, cv::Mat* radiance, cv::Mat* depth = nullptr) const;
  /// Frame i with the shutter open for `exposure_s` (the camera's exposure of that frame): the number of
  /// sub-frame renders scales with it (motion_blur_samples at exposure_time_s, at most 16).
  void renderFrame(const TrajectoryParams& traj, int frame, double exposure_s, cv::Mat* radiance,
                   cv::Mat* depth = nullptr) const;

  /// Casts the ray of pixel (u, v) (any sub-pixel position) from pose T_W_C. Returns false when the
  /// camera cannot unproject it or nothing is hit. p_W: hit point in the world; depth: z in the camera frame.
  bool castPixel(const Eigen::Isometry3d& T_W_C, const Eigen::Vector2d& uv, Eigen::Vector3d* p_W,
                 double* depth = nullptr) const;

  /// Places this renderer's camera in a rig: every trajectory pose T_W_C0 (the rig's reference camera,
  /// whose pose the trajectory gives) becomes T_W_C0 * T_C0_C (e.g. the right camera of a stereo pair).
  void setPoseInRig(const Eigen::Isometry3d& T_C0_C);
  /// This camera's pose at trajectory time t (the trajectory pose, moved by the rig offset).
  Eigen::Isometry3d cameraPose(const TrajectoryParams& traj, double t) const;
  /// T_C0_C set by setPoseInRig (identity by default).
  const Eigen::Isometry3d& poseInRig() const { return T_C0_C_; }

  const CameraModel& camera() const { return *camera_; }
  const CameraModelPtr& cameraPtr() const { return camera_; }
  const Scene& scene() const { return *scene_; }
  const SimParams& params() const { return params_; }
  double frameTime(int frame) const { return frame / params_.rate_hz; }
  int64_t frameStampNs(int frame) const;

 private:
  /// Renders 16 pixels of row r starting at column c0 (supersample 1) with the candidate boxes:
  /// structure-of-arrays passes the compiler vectorizes, then the texture fetches.
  void renderSpan(const Eigen::Matrix3f& R, const Eigen::Vector3f& o, int r, int c0, int n, const int* cand, int nc,
                  float* out, float* dep) const;
  /// Frame i: average of n renders over the exposure window (n <= 1: the frame's pose only).
  void renderBlurred(const TrajectoryParams& traj, int frame, double exposure_s, int n, cv::Mat* radiance,
                     cv::Mat* depth) const;
  /// Renders tile rows [tr0, tr1).
  void renderTileRows(const Eigen::Isometry3d& T_W_C, int tr0, int tr1, cv::Mat* radiance, cv::Mat* depth) const;

  CameraModelPtr camera_;
  std::shared_ptr<const Scene> scene_;
  SimParams params_;
  bool in_rig_ = false;
  Eigen::Isometry3d T_C0_C_ = Eigen::Isometry3d::Identity();
  int w_ = 0, h_ = 0, ss_ = 1;
  // Per sub-pixel bearing (structure of arrays, row-major pixel, then sub-sample) and per pixel
  // angular footprint (rad) for the mip level; valid = 0 where unprojection failed.
  std::vector<float> bx_, by_, bz_, footprint_;
  std::vector<uint8_t> valid_;
  // Box culling: the rays of a kTile x kTile tile lie in a cone (axis in the camera frame, half-angle);
  // only boxes whose bounding sphere meets the cone are intersected.
  static constexpr int kTile = 16;
  int tiles_x_ = 0, tiles_y_ = 0;
  std::vector<Eigen::Vector3f> tile_axis_;
  std::vector<float> tile_half_angle_;
  float max_lod_ = 0.f;  // span renderer: LOD bound valid for every texture of the scene
};

}  // namespace iraf_vo
