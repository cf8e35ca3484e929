#include "iraf_vo/sim/image_formation.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace iraf_vo {

namespace {
constexpr double kMaxBlurPx = 64.0;  // longest blur of a real image (a shift of the view within one exposure)

const LightProfile& checked(const LightProfile& p) {
  const std::string err = validate(p);
  if (!err.empty()) throw std::invalid_argument("light profile '" + p.name + "': " + err);
  return p;
}

/// Line kernel of `length` px along `dir` (normalised to sum 1).
cv::Mat lineKernel(double length, const cv::Point2d& dir) {
  const int len = std::max(1, static_cast<int>(std::lround(length)));
  const int ks = len | 1;
  cv::Mat k = cv::Mat::zeros(ks, ks, CV_32F);
  const double c = 0.5 * (ks - 1), half = 0.5 * (len - 1);
  cv::line(k, cv::Point(cvRound(c - dir.x * half), cvRound(c - dir.y * half)),
           cv::Point(cvRound(c + dir.x * half), cvRound(c + dir.y * half)), cv::Scalar(1.0), 1, cv::LINE_AA);
  return k / cv::sum(k)[0];
}
}  // namespace

ImageFormation::ImageFormation(const LightProfile& profile, CameraModelPtr camera, uint64_t noise_stream)
    : profile_(checked(profile)),
      camera_(std::move(camera)),
      noise_stream_(noise_stream),
      sensor_(profile.sensor),
      ae_(profile.ae) {}

bool ImageFormation::needsGeometry() const {
  return profile_.flashlight.enabled || (profile_.glare.enabled && !lamps_.empty());
}

const cv::Mat& ImageFormation::bearings(int w, int h) const {
  if (!camera_ || (!bearings_.empty() && bearings_.cols == w && bearings_.rows == h)) return bearings_;
  bearings_.create(h, w, CV_32FC3);
  for (int r = 0; r < h; ++r) {
    cv::Vec3f* b = bearings_.ptr<cv::Vec3f>(r);
    for (int c = 0; c < w; ++c) {
      Eigen::Vector3d v;
      if (camera_->unproject(Eigen::Vector2d(c, r), &v) && v.allFinite() && v.norm() > 1e-9) {
        v.normalize();
        b[c] = cv::Vec3f(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
      } else {
        b[c] = cv::Vec3f(0.f, 0.f, 0.f);
      }
    }
  }
  return bearings_;
}

void ImageFormation::applyFlashlight(const FrameGeometry* geometry, cv::Mat* irr) const {
  const FlashlightParams& f = profile_.flashlight;
  const int w = irr->cols, h = irr->rows;
  const cv::Mat& bear = bearings(w, h);
  const bool have_depth = geometry && !geometry->depth.empty() && geometry->depth.size() == irr->size();
  const float sigma = static_cast<float>(f.half_angle_deg * M_PI / 180.0 / std::sqrt(2.0 * std::log(2.0)));
  const float k = -0.5f / (sigma * sigma), d0 = static_cast<float>(f.reference_distance_m);
  const float amb = static_cast<float>(f.ambient), in = static_cast<float>(f.intensity);
  const float cx = 0.5f * (w - 1), cy = 0.5f * (h - 1);
  const float quarter_diag = 0.25f * std::sqrt(static_cast<float>(w * w + h * h));
  const float half = static_cast<float>(f.half_angle_deg * M_PI / 180.0);
  for (int r = 0; r < h; ++r) {
    float* p = irr->ptr<float>(r);
    const float* z = have_depth ? geometry->depth.ptr<float>(r) : nullptr;
    const cv::Vec3f* b = bear.empty() ? nullptr : bear.ptr<cv::Vec3f>(r);
    for (int c = 0; c < w; ++c) {
      float angle, dist = d0;
      if (b) {
        if (b[c][2] == 0.f && b[c][0] == 0.f && b[c][1] == 0.f) {  // no bearing: outside the lens' view
          p[c] *= amb;
          continue;
        }
        angle = std::acos(std::min(1.f, std::max(-1.f, b[c][2])));
      } else {
        angle = half * std::hypot(c - cx, r - cy) / quarter_diag;
      }
      if (z) {
        if (z[c] == 0.f) {  // the ray hit nothing: too far for the cone
          p[c] *= amb;
          continue;
        }
        const float bz = b ? b[c][2] : std::cos(angle);
        dist = std::max(0.1f, std::abs(z[c] / (std::abs(bz) > 1e-3f ? bz : 1e-3f)));
      }
      p[c] *= amb + in * std::exp(k * angle * angle) * (d0 / dist) * (d0 / dist);
    }
  }
}

void ImageFormation::applyGlare(const FrameGeometry& geometry, cv::Mat* irr) const {
  const int w = irr->cols, h = irr->rows;
  const cv::Mat& bear = bearings(w, h);
  if (bear.empty() || geometry.depth.size() != irr->size()) return;
  const Eigen::Matrix3f R = geometry.T_W_C.linear().cast<float>();
  const Eigen::Vector3f o = geometry.T_W_C.translation().cast<float>();
  const float inv_r2 = static_cast<float>(1.0 / (profile_.glare.radius_m * profile_.glare.radius_m));
  const float g = static_cast<float>(profile_.glare.gain);
  std::vector<Eigen::Vector3f> lamps;
  for (const Eigen::Vector3d& l : lamps_) lamps.push_back(l.cast<float>());
  for (int r = 0; r < h; ++r) {
    float* p = irr->ptr<float>(r);
    const float* z = geometry.depth.ptr<float>(r);
    const cv::Vec3f* b = bear.ptr<cv::Vec3f>(r);
    for (int c = 0; c < w; ++c) {
      if (z[c] == 0.f || std::abs(b[c][2]) < 1e-3f) continue;
      const Eigen::Vector3f pw = o + R * (Eigen::Vector3f(b[c][0], b[c][1], b[c][2]) * (z[c] / b[c][2]));
      float boost = 0.f;
      for (const Eigen::Vector3f& l : lamps) {
        const float q = (pw - l).squaredNorm() * inv_r2;
        boost += std::exp(-0.5f * q * q);  // flat top, soft edge
      }
      p[c] *= 1.f + g * std::min(1.f, boost);
    }
  }
}

void ImageFormation::illuminate(int frame, const cv::Mat& radiance, const FrameGeometry* geometry,
                                cv::Mat* irradiance) const {
  applyIllumination(radiance, frame, profile_.scene, irradiance);
  if (profile_.flashlight.enabled) applyFlashlight(geometry, irradiance);
  if (profile_.glare.enabled && geometry && !lamps_.empty()) applyGlare(*geometry, irradiance);
}

double ImageFormation::meterGrey(const cv::Mat& image, const cv::Mat& radiance) const {
  const cv::Rect roi(image.cols / 5, image.rows / 5, image.cols - 2 * (image.cols / 5), image.rows - 2 * (image.rows / 5));
  const double grey = cv::mean(image(roi))[0];
  if (!profile_.meter_against_input) return grey;
  return profile_.ae.target_grey * grey / std::max(1.0, cv::mean(radiance(roi))[0]);
}

void ImageFormation::settle(const cv::Mat& radiance, const FrameGeometry* geometry, int iterations) {
  if (!profile_.ae.enabled) return;
  cv::Mat irr, img;
  illuminate(0, radiance, geometry, &irr);
  for (int i = 0; i < iterations; ++i) {
    sensor_.expose(irr, ae_.next(), profile_.scene.seed * 0x2545F4914F6CDD1DULL + 0xABCDEF00ULL + i, &img);
    ae_.meter(meterGrey(img, radiance));
  }
  ae_.restartHistory();
}

void ImageFormation::capture(int frame, const cv::Mat& radiance, const FrameGeometry* geometry, cv::Mat* out,
                             FrameLight* record, const cv::Point2d& image_motion_px, double frame_period_s) {
  captureWithExposure(frame, ae_.next(), radiance, geometry, out, record, image_motion_px, frame_period_s);
  ae_.meter(meterGrey(*out, radiance));
}

void ImageFormation::captureWithExposure(int frame, const Exposure& e, const cv::Mat& radiance,
                                         const FrameGeometry* geometry, cv::Mat* out, FrameLight* record,
                                         const cv::Point2d& image_motion_px, double frame_period_s) const {
  cv::Mat irr;
  illuminate(frame, radiance, geometry, &irr);
  const double extra = e.time_s - profile_.sensor.reference_exposure_s;
  const double motion = std::hypot(image_motion_px.x, image_motion_px.y);
  if (extra > 0.0 && motion > 0.0 && frame_period_s > 0.0) {
    const double length = std::min(kMaxBlurPx, motion * extra / frame_period_s);
    if (length >= 1.5)
      cv::filter2D(irr, irr, -1, lineKernel(length, image_motion_px / motion), cv::Point(-1, -1), 0,
                   cv::BORDER_REFLECT);
  }
  uint64_t seed = profile_.scene.seed * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(frame) * 7919ULL + 1;
  if (noise_stream_ > 0) seed = mixSeed(seed ^ (noise_stream_ * 0xD1B54A32D192ED03ULL));
  sensor_.expose(irr, e, seed, out);
  if (record) {
    record->frame = frame;
    record->exposure = e;
    record->illumination = globalGain(profile_.scene, frame);
    record->mean_grey = cv::mean(*out)[0];
    record->saturated = cv::countNonZero(*out == 255) / static_cast<double>(out->total());
  }
}

bool writeExposureCsv(const std::string& path, const std::vector<FrameLight>& rows, std::string* error) {
  std::ofstream f(path);
  if (!f) {
    if (error) *error = path + ": cannot write";
    return false;
  }
  f << "# frame,exposure_ms,gain,illumination,mean_grey,saturated\n";
  char buf[160];
  for (const FrameLight& r : rows) {
    std::snprintf(buf, sizeof(buf), "%d,%.4f,%.4f,%.6g,%.2f,%.4f\n", r.frame, r.exposure.time_s * 1e3, r.exposure.gain,
                  r.illumination, r.mean_grey, r.saturated);
    f << buf;
  }
  if (!f) {
    if (error) *error = path + ": write failed";
    return false;
  }
  return true;
}

}  // namespace iraf_vo
