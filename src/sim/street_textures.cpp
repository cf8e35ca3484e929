// Outdoor albedo textures of the street scene (facades, asphalt, foliage, sky). Sizes in meters are
// converted with texels_per_m, so the statistics do not depend on the texture resolution.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "iraf_vo/sim/scene_presets.h"

namespace iraf_vo {

namespace {

void checkSize(int w, int h, const char* what) {
  if (w < 16 || h < 16 || (w & (w - 1)) || (h & (h - 1)))
    throw std::invalid_argument(std::string(what) + ": sides must be powers of two >= 16 (got " + std::to_string(w) +
                                "x" + std::to_string(h) + ")");
}

/// Sum of value-noise octaves (random values on grids of cell_m meters, bicubic upsampling), zero mean.
cv::Mat valueNoise(int w, int h, double tpm, const std::vector<std::pair<double, double>>& cells_amps, cv::RNG* rng) {
  cv::Mat acc(h, w, CV_32F, cv::Scalar(0));
  for (const auto& ca : cells_amps) {
    const int cw = std::max(2, static_cast<int>(w / (ca.first * tpm)));
    const int ch = std::max(2, static_cast<int>(h / (ca.first * tpm)));
    cv::Mat small(ch, cw, CV_32F), up;
    rng->fill(small, cv::RNG::UNIFORM, -ca.second, ca.second);
    cv::resize(small, up, acc.size(), 0, 0, cv::INTER_CUBIC);
    acc += up;
  }
  return acc;
}

cv::Mat toAlbedo(const cv::Mat& f) {
  cv::Mat out;
  f.convertTo(out, CV_8U);  // saturates to [0, 255]
  return out;
}

// Adds v to the pixels of f inside r, a rectangle already clipped to f: a patch drawn at the tile's edge clips to an
// empty rectangle, which adds nothing (OpenCV cannot add to an empty view).
void addInside(cv::Mat& f, const cv::Rect& r, double v) {
  if (r.area() > 0) f(r) += v;
}

cv::Rect metersRect(double x_m, double y_m, double w_m, double h_m, double tpm) {
  return cv::Rect(cvRound(x_m * tpm), cvRound(y_m * tpm), std::max(1, cvRound(w_m * tpm)), std::max(1, cvRound(h_m * tpm)));
}

}  // namespace

cv::Mat makeFacadeTexture(int w, int h, double tpm, uint64_t seed) {
  checkSize(w, h, "makeFacadeTexture");
  cv::RNG rng(seed * 0x2545F4914F6CDD1Dull + 77);
  const double base = rng.uniform(95.0, 190.0);
  cv::Mat f = valueNoise(w, h, tpm, {{4.0, 14.0}, {1.0, 10.0}, {0.25, 7.0}, {0.06, 5.0}, {0.02, 4.0}}, &rng);
  f += base;
  const double W = w / tpm, H = h / tpm;
  const double floor_h = H / 5;  // the texture wraps vertically after 5 floors
  const int cols = rng.uniform(std::max(2, static_cast<int>(W / 3.6)), std::max(3, static_cast<int>(W / 2.4) + 1));
  const double spacing = W / cols;
  const double ww = std::min(spacing - 0.5, rng.uniform(0.9, 1.6)), wh = std::min(floor_h - 0.9, rng.uniform(1.3, 1.9));
  const double frame_tone = rng.uniform(0.0, 1.0) < 0.6 ? std::min(245.0, base + 45) : rng.uniform(30.0, 70.0);
  const bool mullions = rng.uniform(0.0, 1.0) < 0.6;
  for (int fl = 0; fl < 5; ++fl) {
    // Cornice between floors: a 10-20 cm band, lighter or darker than the plaster.
    const double band = rng.uniform(0.1, 0.2);
    addInside(f, metersRect(0, fl * floor_h, W, band, tpm) & cv::Rect(0, 0, w, h), rng.uniform(-35.0, 35.0));
    for (int c = 0; c < cols; ++c) {
      const double x0 = c * spacing + (spacing - ww) / 2, y0 = fl * floor_h + 0.45 * (floor_h - wh);
      const cv::Rect frame = metersRect(x0 - 0.07, y0 - 0.07, ww + 0.14, wh + 0.14, tpm) & cv::Rect(0, 0, w, h);
      const cv::Rect glass = metersRect(x0, y0, ww, wh, tpm) & cv::Rect(0, 0, w, h);
      const cv::Rect sill = metersRect(x0 - 0.12, y0 + wh + 0.07, ww + 0.24, 0.06, tpm) & cv::Rect(0, 0, w, h);
      f(frame).setTo(frame_tone + rng.uniform(-8.0, 8.0));
      f(sill).setTo(std::min(250.0, base + rng.uniform(20.0, 60.0)));
      // Glass: dark with a diagonal reflection gradient; some windows lit, some with light curtains.
      const double u = rng.uniform(0.0, 1.0);
      const double g0 = u < 0.08 ? rng.uniform(170.0, 230.0) : rng.uniform(18.0, 70.0);
      cv::Mat gl = f(glass);
      for (int r = 0; r < gl.rows; ++r) {
        float* p = gl.ptr<float>(r);
        for (int k = 0; k < gl.cols; ++k)
          p[k] = static_cast<float>(g0 + 35.0 * (0.5 * r / std::max(1, gl.rows) + 0.5 * k / std::max(1, gl.cols)));
      }
      if (u > 0.75) {  // curtain covering the top part
        const int ch = static_cast<int>(gl.rows * rng.uniform(0.3, 0.7));
        gl(cv::Rect(0, 0, gl.cols, std::max(1, ch))) += rng.uniform(60.0, 120.0);
      }
      if (mullions) {
        const int t = std::max(1, cvRound(0.05 * tpm));
        cv::line(f, cv::Point(glass.x + glass.width / 2, glass.y), cv::Point(glass.x + glass.width / 2, glass.br().y),
                 cv::Scalar(frame_tone), t);
        cv::line(f, cv::Point(glass.x, glass.y + glass.height / 3), cv::Point(glass.br().x, glass.y + glass.height / 3),
                 cv::Scalar(frame_tone), t);
      }
      // Grime streak below the sill.
      if (rng.uniform(0.0, 1.0) < 0.4) {
        const cv::Rect streak = metersRect(x0 + ww * 0.2, y0 + wh + 0.13, ww * 0.6, rng.uniform(0.3, 1.0), tpm) &
                                cv::Rect(0, 0, w, h);
        addInside(f, streak, -rng.uniform(8.0, 25.0));
      }
    }
  }
  // Signs / posters: a few high-contrast rectangles with text-like bars.
  const int n_sign = std::max(1, static_cast<int>(W / 12));
  for (int i = 0; i < n_sign; ++i) {
    const cv::Rect s = metersRect(rng.uniform(0.0, W - 3), rng.uniform(0.0, H - 1), rng.uniform(1.0, 3.0),
                                  rng.uniform(0.4, 0.9), tpm) & cv::Rect(0, 0, w, h);
    const double bg = rng.uniform(0.0, 1.0) < 0.5 ? rng.uniform(200.0, 245.0) : rng.uniform(15.0, 50.0);
    f(s).setTo(bg);
    for (int k = 0; k < 6; ++k) {
      const int x = s.x + static_cast<int>(s.width * (0.08 + 0.15 * k)), y = s.y + s.height / 3;
      cv::rectangle(f, cv::Rect(x, y, std::max(1, s.width / 10), std::max(1, s.height / 3)), cv::Scalar(255 - bg), cv::FILLED);
    }
  }
  cv::Mat grain(h, w, CV_32F);
  rng.fill(grain, cv::RNG::NORMAL, 0.0, 4.0);
  f += grain;
  return toAlbedo(f);
}

cv::Mat makeAsphaltTexture(int w, int h, double tpm, uint64_t seed) {
  checkSize(w, h, "makeAsphaltTexture");
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 991);
  cv::Mat f = valueNoise(w, h, tpm, {{3.0, 10.0}, {0.6, 7.0}, {0.12, 6.0}, {0.03, 6.0}}, &rng);
  f += 78.0;
  // Aggregate: texel-level stones (bright and dark), slightly smoothed.
  cv::Mat grain(h, w, CV_32F), g2;
  rng.fill(grain, cv::RNG::NORMAL, 0.0, 16.0);
  cv::GaussianBlur(grain, g2, cv::Size(3, 3), 0.7);
  f += g2;
  const double W = w / tpm, H = h / tpm, area = W * H;
  auto pt = [&]() { return cv::Point(rng.uniform(0, w), rng.uniform(0, h)); };
  // Repair patches (0.5-4 m, darker or lighter) with hard edges.
  for (int i = 0; i < static_cast<int>(area / 25); ++i) {
    const cv::Rect r = metersRect(rng.uniform(0.0, W), rng.uniform(0.0, H), rng.uniform(0.5, 4.0), rng.uniform(0.5, 3.0),
                                  tpm) & cv::Rect(0, 0, w, h);
    addInside(f, r, rng.uniform(-22.0, 18.0));
  }
  // Cracks: random walks, 1-3 texels wide.
  for (int i = 0; i < static_cast<int>(area / 12); ++i) {
    cv::Point p = pt();
    double ang = rng.uniform(0.0, 2 * M_PI);
    const int steps = rng.uniform(5, 30);
    for (int k = 0; k < steps; ++k) {
      ang += rng.uniform(-0.6, 0.6);
      const cv::Point q(p.x + cvRound(0.08 * tpm * std::cos(ang)), p.y + cvRound(0.08 * tpm * std::sin(ang)));
      cv::line(f, p, q, cv::Scalar(rng.uniform(25.0, 45.0)), rng.uniform(1, 4), cv::LINE_AA);
      p = q;
    }
  }
  // Oil stains (soft dark blobs) and manholes (dark disc with a bright ring).
  for (int i = 0; i < static_cast<int>(area / 30); ++i)
    cv::ellipse(f, cv::RotatedRect(pt(), cv::Size2f(rng.uniform(0.2f, 1.0f) * tpm, rng.uniform(0.15f, 0.6f) * tpm),
                                   rng.uniform(0.f, 180.f)), cv::Scalar(rng.uniform(35.0, 60.0)), cv::FILLED, cv::LINE_AA);
  for (int i = 0; i < std::max(1, static_cast<int>(area / 150)); ++i) {
    const cv::Point c = pt();
    cv::circle(f, c, cvRound(0.32 * tpm), cv::Scalar(120), std::max(1, cvRound(0.04 * tpm)), cv::LINE_AA);
    cv::circle(f, c, cvRound(0.28 * tpm), cv::Scalar(45), cv::FILLED, cv::LINE_AA);
  }
  // Lane-marking dashes (3 m x 0.15 m along x, worn) and a few stop lines (across).
  for (int i = 0; i < static_cast<int>(area / 60); ++i) {
    const bool dash = rng.uniform(0.0, 1.0) < 0.8;
    const cv::Rect r = metersRect(rng.uniform(0.0, W), rng.uniform(0.0, H), dash ? 3.0 : 0.4, dash ? 0.15 : 3.0, tpm) &
                       cv::Rect(0, 0, w, h);
    cv::Mat roi = f(r);
    roi.convertTo(roi, CV_32F, 0.55, 0.45 * 230.0);
  }
  f = cv::max(f, 8.0);
  return toAlbedo(f);
}

cv::Mat makeFoliageTexture(int w, int h, double tpm, uint64_t seed) {
  checkSize(w, h, "makeFoliageTexture");
  cv::RNG rng(seed * 0xD1B54A32D192ED03ull + 5);
  cv::Mat f = valueNoise(w, h, tpm, {{1.0, 20.0}, {0.3, 15.0}}, &rng);
  f += 55.0;
  const double area = (w / tpm) * (h / tpm);
  for (int i = 0; i < static_cast<int>(area * 300); ++i) {
    const float r = static_cast<float>(0.015 * std::pow(5.0, rng.uniform(0.0, 1.0)) * tpm);
    cv::ellipse(f, cv::RotatedRect(cv::Point2f(rng.uniform(0.f, (float)w), rng.uniform(0.f, (float)h)),
                                   cv::Size2f(2 * r, 2 * r * rng.uniform(0.4f, 1.0f)), rng.uniform(0.f, 180.f)),
                cv::Scalar(rng.uniform(25.0, 150.0)), cv::FILLED, cv::LINE_AA);
  }
  return toAlbedo(f);
}

cv::Mat makeSkyTexture(int w, int h, double tpm, uint64_t seed) {
  checkSize(w, h, "makeSkyTexture");
  cv::RNG rng(seed * 0x94D049BB133111EBull + 17);
  cv::Mat f = valueNoise(w, h, tpm, {{10.0, 30.0}, {4.0, 20.0}, {2.0, 8.0}}, &rng);
  f += 205.0;
  return toAlbedo(f);
}

}  // namespace iraf_vo
