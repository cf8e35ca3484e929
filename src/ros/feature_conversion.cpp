#include "iraf_vo/ros/feature_conversion.h"

#include <cmath>
#include <cstring>
#include <sstream>

namespace iraf_vo {

void toMsg(const FeatureFrame& f, const std_msgs::Header& header, Features* m) {
  m->header = header;
  m->width = static_cast<uint32_t>(std::max(0, f.width));
  m->height = static_cast<uint32_t>(std::max(0, f.height));
  m->scale_factor = f.scale_factor;
  const size_t n = f.keypoints.size();
  m->x.resize(n);
  m->y.resize(n);
  m->size.resize(n);
  m->angle.resize(n);
  m->response.resize(n);
  m->octave.resize(n);
  m->fast_threshold.resize(n);
  m->stability.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const cv::KeyPoint& k = f.keypoints[i];
    m->x[i] = k.pt.x;
    m->y[i] = k.pt.y;
    m->size[i] = k.size;
    m->angle[i] = k.angle;
    m->response[i] = k.response;
    m->octave[i] = static_cast<int8_t>(k.octave);
    m->fast_threshold[i] = static_cast<int16_t>(k.class_id);
    m->stability[i] = i < f.stability.size() ? f.stability[i] : 1.f;
  }
  m->descriptors.resize(n * 32);
  if (n > 0 && f.descriptors.rows == static_cast<int>(n) && f.descriptors.cols == 32 && f.descriptors.type() == CV_8U) {
    for (size_t i = 0; i < n; ++i) std::memcpy(&m->descriptors[32 * i], f.descriptors.ptr<uint8_t>(static_cast<int>(i)), 32);
  }
  const FeatureStats& s = f.stats;
  m->global_threshold = static_cast<float>(s.global_threshold);
  m->cell_threshold_min = static_cast<float>(s.cell_threshold_min);
  m->cell_threshold_median = static_cast<float>(s.cell_threshold_median);
  m->cell_threshold_max = static_cast<float>(s.cell_threshold_max);
  m->entropy = static_cast<float>(s.entropy);
  m->gradient = static_cast<float>(s.gradient);
  m->detected = s.detected;
  m->culled = s.culled;
  m->brightness = static_cast<int8_t>(s.brightness);
  m->ms_threshold = static_cast<float>(s.ms_threshold);
  m->ms_detect = static_cast<float>(s.ms_detect);
  m->ms_cull = static_cast<float>(s.ms_cull);
  m->signal_measured = f.signal.measured;
  m->signal_mean = static_cast<float>(f.signal.mean);
  m->signal_noise = static_cast<float>(f.signal.noise_sigma);
  m->signal_contrast = static_cast<float>(f.signal.contrast);
  m->signal_snr = static_cast<float>(f.signal.snr);
  m->signal_clipped = static_cast<float>(f.signal.clipped);
}

double scaleFactorFromSizes(const Features& m) {
  for (size_t i = 0; i < m.octave.size() && i < m.size.size(); ++i)
    if (m.octave[i] > 0 && m.size[i] > 31.0f) return std::pow(m.size[i] / 31.0, 1.0 / m.octave[i]);
  return 0.0;
}

bool fromMsg(const Features& m, FeatureFrame* f, std::string* error, std::string* warning) {
  const size_t n = m.x.size();
  std::ostringstream e;
  if (m.y.size() != n || m.size.size() != n || m.angle.size() != n || m.response.size() != n ||
      m.octave.size() != n || m.fast_threshold.size() != n || m.stability.size() != n)
    e << "keypoint arrays differ in length (x " << n << ", y " << m.y.size() << ", size " << m.size.size() << ", angle "
      << m.angle.size() << ", response " << m.response.size() << ", octave " << m.octave.size() << ", fast_threshold "
      << m.fast_threshold.size() << ", stability " << m.stability.size() << ")";
  else if (m.descriptors.size() != 32 * n)
    e << "descriptors has " << m.descriptors.size() << " bytes, expected 32 x " << n;
  else if (m.scale_factor != 0.0 && !(m.scale_factor > 1.0 && m.scale_factor <= 4.0))
    e << "scale_factor " << m.scale_factor << " is not in (1, 4]";
  else
    for (size_t i = 0; i < n; ++i)
      if (!std::isfinite(m.x[i]) || !std::isfinite(m.y[i])) {
        e << "keypoint " << i << " has a non-finite coordinate";
        break;
      }
  if (!e.str().empty()) {
    if (error) *error = "Features message (stamp " + std::to_string(m.header.stamp.toSec()) + "): " + e.str();
    return false;
  }
  FeatureFrame out;
  out.stamp = m.header.stamp.toSec();
  out.width = static_cast<int>(m.width);
  out.height = static_cast<int>(m.height);
  out.scale_factor = m.scale_factor;
  if (m.scale_factor == 0.0) {  // an older sender
    const double estimate = scaleFactorFromSizes(m);
    out.scale_factor = estimate > 1.0 && estimate <= 4.0 ? estimate : 1.2;
    if (warning) {
      std::ostringstream w;
      w << "Features message without scale_factor: using " << out.scale_factor
        << (estimate > 1.0 && estimate <= 4.0 ? " (from the keypoint sizes)" : " (the default)");
      *warning = w.str();
    }
  }
  out.keypoints.resize(n);
  out.stability.assign(m.stability.begin(), m.stability.end());
  for (size_t i = 0; i < n; ++i) {
    cv::KeyPoint& k = out.keypoints[i];
    k.pt = cv::Point2f(m.x[i], m.y[i]);
    k.size = m.size[i];
    k.angle = m.angle[i];
    k.response = m.response[i];
    k.octave = m.octave[i];
    k.class_id = m.fast_threshold[i];
  }
  out.descriptors.create(static_cast<int>(n), 32, CV_8U);
  if (n > 0) std::memcpy(out.descriptors.data, m.descriptors.data(), 32 * n);
  FeatureStats& s = out.stats;
  s.global_threshold = m.global_threshold;
  s.cell_threshold_min = m.cell_threshold_min;
  s.cell_threshold_median = m.cell_threshold_median;
  s.cell_threshold_max = m.cell_threshold_max;
  s.entropy = m.entropy;
  s.gradient = m.gradient;
  s.detected = m.detected;
  s.culled = m.culled;
  s.brightness = m.brightness;
  s.ms_threshold = m.ms_threshold;
  s.ms_detect = m.ms_detect;
  out.signal.measured = m.signal_measured;
  out.signal.mean = m.signal_mean;
  out.signal.noise_sigma = m.signal_noise;
  out.signal.contrast = m.signal_contrast;
  out.signal.snr = m.signal_snr;
  out.signal.clipped = m.signal_clipped;
  s.ms_cull = m.ms_cull;
  *f = std::move(out);
  return true;
}

}  // namespace iraf_vo
