#include "iraf_vo/sim/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace iraf_vo {

namespace {
// Below this mean the electron count is drawn exactly (Knuth's product of uniforms); above it the
// Gaussian approximation N(lambda, lambda) is within 1 % in variance and much faster.
constexpr float kExactPoissonBelow = 24.f;

float poissonSmall(float lambda, cv::RNG& rng) {
  const float limit = std::exp(-lambda);
  float prod = rng.uniform(0.f, 1.f);
  int k = 0;
  while (prod > limit) {
    prod *= rng.uniform(0.f, 1.f);
    ++k;
  }
  return static_cast<float>(k);
}
}  // namespace

uint64_t mixSeed(uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

std::string validate(const SensorParams& p) {
  std::ostringstream err;
  if (!(p.full_well_e > 0.0)) err << "full_well_e must be > 0; ";
  if (!(p.dn_per_electron > 0.0)) err << "dn_per_electron must be > 0; ";
  if (!(p.read_noise_e >= 0.0)) err << "read_noise_e must be >= 0; ";
  if (!(p.adc_noise_dn >= 0.0)) err << "adc_noise_dn must be >= 0; ";
  if (!(p.black_level_dn >= 0.0 && p.black_level_dn < 255.0)) err << "black_level_dn must be in [0, 255); ";
  if (!(p.reference_exposure_s > 0.0)) err << "reference_exposure_s must be > 0; ";
  return err.str();
}

SensorModel::SensorModel(const SensorParams& params) : p_(params) {
  const std::string err = validate(params);
  if (!err.empty()) throw std::invalid_argument("SensorModel: " + err);
}

double SensorModel::expectedDn(double irradiance, const Exposure& e) const {
  const double electrons = std::min(p_.full_well_e, std::max(0.0, irradiance) * e.time_s / p_.reference_exposure_s /
                                                        p_.dn_per_electron);
  return electrons * p_.dn_per_electron * e.gain + p_.black_level_dn;
}

double SensorModel::noiseVarianceDn(double mean_dn, double gain) const {
  const double k = p_.dn_per_electron * gain;  // DN per electron at this gain
  const double signal = std::max(0.0, mean_dn - p_.black_level_dn);
  return k * signal + k * k * p_.read_noise_e * p_.read_noise_e + p_.adc_noise_dn * p_.adc_noise_dn + 1.0 / 12.0;
}

void SensorModel::expose(const cv::Mat& irradiance, const Exposure& e, uint64_t noise_seed, cv::Mat* out) const {
  if (irradiance.empty()) throw std::invalid_argument("SensorModel::expose: empty image");
  if (irradiance.type() != CV_32FC1)
    throw std::invalid_argument("SensorModel::expose: irradiance must be CV_32FC1 (got type " +
                                std::to_string(irradiance.type()) + ")");
  if (!(e.time_s >= 0.0) || !(e.gain > 0.0))
    throw std::invalid_argument("SensorModel::expose: exposure time must be >= 0 and gain > 0");
  const int w = irradiance.cols, h = irradiance.rows;
  cv::RNG rng(mixSeed(noise_seed));
  cv::Mat shot(h, w, CV_32F), read(h, w, CV_32F);
  rng.fill(shot, cv::RNG::NORMAL, 0.0, 1.0);
  rng.fill(read, cv::RNG::NORMAL, 0.0, 1.0);
  cv::RNG small_rng(mixSeed(noise_seed ^ 0x5bd1e995ULL));
  const float to_e = static_cast<float>(e.time_s / p_.reference_exposure_s / p_.dn_per_electron);
  const float full = static_cast<float>(p_.full_well_e);
  const float k = static_cast<float>(p_.dn_per_electron * e.gain);
  const float read_dn = static_cast<float>(std::sqrt(std::pow(p_.dn_per_electron * e.gain * p_.read_noise_e, 2) +
                                                     p_.adc_noise_dn * p_.adc_noise_dn));
  const float black = static_cast<float>(p_.black_level_dn);
  out->create(h, w, CV_8UC1);
  for (int r = 0; r < h; ++r) {
    const float* in = irradiance.ptr<float>(r);
    const float* zs = shot.ptr<float>(r);
    const float* zr = read.ptr<float>(r);
    uint8_t* o = out->ptr<uint8_t>(r);
    for (int c = 0; c < w; ++c) {
      const float lambda = std::max(0.f, in[c]) * to_e;
      float electrons = lambda < kExactPoissonBelow ? poissonSmall(lambda, small_rng)
                                                    : std::round(lambda + std::sqrt(lambda) * zs[c]);
      electrons = std::min(full, std::max(0.f, electrons));
      const float dn = electrons * k + zr[c] * read_dn + black;
      o[c] = cv::saturate_cast<uint8_t>(dn);  // rounds to the nearest DN, clips to [0, 255]
    }
  }
}

}  // namespace iraf_vo
