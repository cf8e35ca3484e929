// Helpers shared by the tests: locating real data in ../shared (skip when absent) and small images.
#pragma once

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <cmath>
#include <fstream>
#include <string>
#include <sys/stat.h>

namespace iraf_vo_test {

inline bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

/// ../shared/data/<rel>, or "" when the shared data is not there (the caller skips).
inline std::string sharedData(const std::string& rel) {
  const std::string p = std::string(IRAF_VO_SHARED_DIR) + "/data/" + rel;
  return exists(p) ? p : std::string();
}

/// EuRoC MH_01 frame `index` (row of data.csv) from the shared folder (empty Mat when absent).
inline cv::Mat eurocFrame(int index = 0) {
  const std::string dir = sharedData("euroc_mh01_600/mav0/cam0");
  if (dir.empty()) return cv::Mat();
  std::ifstream csv(dir + "/data.csv");
  std::string line;
  int row = 0;
  while (std::getline(csv, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (row++ == index) {
      const std::string name = line.substr(line.find(',') + 1);
      return cv::imread(dir + "/data/" + name.substr(0, name.find_last_not_of(" \r") + 1), cv::IMREAD_GRAYSCALE);
    }
  }
  return cv::Mat();
}

/// Shannon entropy of an 8-bit image's histogram, in bits.
inline double entropyBits(const cv::Mat& gray) {
  int h[256] = {0};
  for (int r = 0; r < gray.rows; ++r)
    for (int c = 0; c < gray.cols; ++c) ++h[gray.at<uint8_t>(r, c)];
  const double n = static_cast<double>(gray.total());
  double e = 0.0;
  for (int v : h)
    if (v > 0) e -= (v / n) * std::log2(v / n);
  return e;
}

/// A deterministic textured test image (smooth noise at several scales + squares), mean ~ 120.
inline cv::Mat texturedImage(int w = 320, int h = 240, unsigned seed = 7) {
  cv::RNG rng(seed);
  cv::Mat acc(h, w, CV_32F, cv::Scalar(0));
  for (int scale : {4, 16, 48}) {
    cv::Mat small((h + scale - 1) / scale + 1, (w + scale - 1) / scale + 1, CV_32F);
    rng.fill(small, cv::RNG::UNIFORM, 0.f, 1.f);
    cv::Mat up;
    cv::resize(small, up, cv::Size(), scale, scale, cv::INTER_CUBIC);
    acc += up(cv::Rect(0, 0, w, h)) * (scale / 68.0f);
  }
  cv::Mat out;
  acc.convertTo(out, CV_8U, 200.0, 20.0);
  for (int i = 0; i < 12; ++i) {
    const int x = rng.uniform(0, w - 20), y = rng.uniform(0, h - 20);
    cv::rectangle(out, cv::Rect(x, y, 12, 12), cv::Scalar(rng.uniform(0, 2) * 220 + 20), cv::FILLED);
  }
  return out;
}

/// An 8-bit image plus Gaussian noise of `sigma` grey levels (rounded, clipped to 8 bits), drawn from `seed`.
inline cv::Mat withNoise(const cv::Mat& img, double sigma, uint64_t seed) {
  cv::Mat noise(img.size(), CV_32F), f, out;
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0, sigma);
  img.convertTo(f, CV_32F);
  cv::Mat(f + noise).convertTo(out, CV_8U);
  return out;
}

}  // namespace iraf_vo_test
