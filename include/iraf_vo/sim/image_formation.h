// Image formation of the simulated camera (ROS-free): one object per sequence applies a LightProfile
// frame after frame. Per frame:
//   irradiance = radiance (DN at the reference exposure) x scene illumination events
//                x flashlight cone (angle, distance^2) x glare lamps        (depth-based parts need depth)
//   [real images] directional blur along the image motion, scaled by the exposure time beyond the reference
//   image      = SensorModel::expose(irradiance, exposure chosen by the auto-exposure, seed of the frame)
//   the auto-exposure meters the image's central region (60 % x 60 %) for a later frame (real images:
//   against the input's own grey there, so that normal light keeps the reference exposure).
// The renderer's shutter is tied to the exposure (Renderer::renderFrame with the frame's exposure time).
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <memory>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/sim/auto_exposure.h"
#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/sensor_model.h"

namespace iraf_vo {

/// What the camera did on one frame (a row of exposure.csv).
struct FrameLight {
  int frame = 0;
  Exposure exposure;
  double illumination = 1.0;  // global scene light of the events (1 = normal light)
  double mean_grey = 0.0;     // of the whole output image
  double saturated = 0.0;     // share of pixels at 255
};

/// Optional per-frame geometry: z-depth (CV_32FC1, m, 0 = no hit) of each pixel and the camera pose.
struct FrameGeometry {
  cv::Mat depth;
  Eigen::Isometry3d T_W_C = Eigen::Isometry3d::Identity();
};

class ImageFormation {
 public:
  /// `camera` (optional) gives each pixel's bearing for the flashlight's angle and the glare's world
  /// points; without it the flashlight's angle comes from the distance to the image centre (the half
  /// angle at a quarter of the diagonal). `noise_stream` > 0 draws sensor noise independent of stream 0's
  /// (the second camera of a stereo pair). Throws std::invalid_argument for a bad profile.
  ImageFormation(const LightProfile& profile, CameraModelPtr camera, uint64_t noise_stream = 0);

  /// The world points of the glare lamps (simulator: hit points of the view's centre along the path).
  void setGlareLamps(const std::vector<Eigen::Vector3d>& lamps) { lamps_ = lamps; }
  /// True when the profile needs FrameGeometry (flashlight distances, glare lamps).
  bool needsGeometry() const;

  /// Exposure of the next frame (decided by the auto-exposure from earlier frames).
  Exposure nextExposure() const { return ae_.next(); }

  /// Lets the auto-exposure converge on `radiance` (e.g. the first frame) before the sequence starts,
  /// as a camera that has been running: `iterations` exposures, metered, not recorded.
  void settle(const cv::Mat& radiance, const FrameGeometry* geometry, int iterations = 40);

  /// Forms frame `frame` from `radiance` (CV_32FC1 or CV_8UC1, DN at the reference exposure) with
  /// nextExposure(); `image_motion_px` (real images): the image's shift over one frame period, for the
  /// blur; `frame_period_s` the period. Writes the CV_8UC1 image and meters it.
  void capture(int frame, const cv::Mat& radiance, const FrameGeometry* geometry, cv::Mat* out,
               FrameLight* record = nullptr, const cv::Point2d& image_motion_px = cv::Point2d(0, 0),
               double frame_period_s = 0.05);

  /// Forms frame `frame` like capture() but with the given exposure and without metering: the second
  /// camera of a pair, which takes the exposure and gain the first camera's auto-exposure chose.
  void captureWithExposure(int frame, const Exposure& exposure, const cv::Mat& radiance, const FrameGeometry* geometry,
                           cv::Mat* out, FrameLight* record = nullptr,
                           const cv::Point2d& image_motion_px = cv::Point2d(0, 0), double frame_period_s = 0.05) const;

  const LightProfile& profile() const { return profile_; }

 private:
  /// irradiance = radiance x events x flashlight x glare (CV_32FC1).
  void illuminate(int frame, const cv::Mat& radiance, const FrameGeometry* geometry, cv::Mat* irradiance) const;
  void applyFlashlight(const FrameGeometry* geometry, cv::Mat* irradiance) const;
  void applyGlare(const FrameGeometry& geometry, cv::Mat* irradiance) const;
  /// Unit bearings (CV_32FC3) of every pixel, computed once; empty without a camera.
  const cv::Mat& bearings(int w, int h) const;
  /// Mean grey of the central 60 % x 60 % (relative to the input's when profile().meter_against_input).
  double meterGrey(const cv::Mat& image, const cv::Mat& radiance) const;

  LightProfile profile_;
  CameraModelPtr camera_;
  uint64_t noise_stream_ = 0;
  SensorModel sensor_;
  AutoExposure ae_;
  std::vector<Eigen::Vector3d> lamps_;
  mutable cv::Mat bearings_;
};

/// exposure.csv: "# frame,exposure_ms,gain,illumination,mean_grey,saturated" then one row per frame.
bool writeExposureCsv(const std::string& path, const std::vector<FrameLight>& rows, std::string* error);

}  // namespace iraf_vo
