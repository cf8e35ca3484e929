#include "iraf_vo/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <sys/stat.h>

#include <opencv2/imgcodecs.hpp>  // IMREAD_* flags
#include <opencv2/imgproc.hpp>

#include "iraf_vo/io/image_codecs.h"

namespace iraf_vo {

namespace {

bool isPow2(int v) { return v > 0 && (v & (v - 1)) == 0; }

bool fileExists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// SceneTexture

SceneTexture::SceneTexture(const cv::Mat& albedo, float texels_per_m) : texels_per_m_(texels_per_m) {
  if (albedo.empty() || albedo.type() != CV_8UC1 || !isPow2(albedo.cols) || !isPow2(albedo.rows))
    throw std::invalid_argument("SceneTexture: albedo must be CV_8UC1 with power-of-two sides (got " +
                                std::to_string(albedo.cols) + "x" + std::to_string(albedo.rows) + ")");
  if (!(texels_per_m > 0.f)) throw std::invalid_argument("SceneTexture: texels_per_m must be > 0");
  levels_.push_back(albedo.clone());
  while (levels_.back().cols > 4 && levels_.back().rows > 4) {
    cv::Mat down;
    cv::pyrDown(levels_.back(), down);  // Gaussian 5x5 + decimation: the box-ish prefilter of a mipmap
    levels_.push_back(down);
  }
  max_lod_ = static_cast<float>(levels_.size() - 1) - 1e-3f;
  for (size_t i = 0; i < levels_.size(); ++i)
    view_.push_back(Level{levels_[i].data, levels_[i].step[0], levels_[i].cols - 1, levels_[i].rows - 1,
                          texels_per_m / static_cast<float>(1 << i)});
}

// ------------------------------------------------------------------------------------------------
// Procedural textures

cv::Mat makeProceduralTexture(int width, int height, double texels_per_m, uint64_t seed) {
  if (!isPow2(width) || !isPow2(height))
    throw std::invalid_argument("makeProceduralTexture: sides must be powers of two");
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 12345);
  const double tpm = texels_per_m;
  cv::Mat acc(height, width, CV_32F, cv::Scalar(0.5));

  // Multi-scale value noise: random values on coarse grids, bicubic upsampling, summed octaves.
  const double cells_m[] = {0.8, 0.4, 0.2, 0.1, 0.05, 0.025};
  const double amps[] = {0.22, 0.16, 0.12, 0.09, 0.07, 0.05};
  for (int o = 0; o < 6; ++o) {
    const int cw = std::max(2, static_cast<int>(width / (cells_m[o] * tpm)));
    const int ch = std::max(2, static_cast<int>(height / (cells_m[o] * tpm)));
    cv::Mat small(ch, cw, CV_32F), up;
    rng.fill(small, cv::RNG::UNIFORM, -1.0, 1.0);
    cv::resize(small, up, acc.size(), 0, 0, cv::INTER_CUBIC);
    acc += amps[o] * up;
  }
  cv::Mat img;
  acc.convertTo(img, CV_8U, 255.0);

  const double area_m2 = (width / tpm) * (height / tpm);
  auto logUniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, rng.uniform(0.0, 1.0)); };
  auto gray = [&]() { return cv::Scalar(rng.uniform(10, 246)); };
  auto pt = [&]() { return cv::Point2f(rng.uniform(0.f, (float)width), rng.uniform(0.f, (float)height)); };

  // Random (partly rotated) rectangles: corners from 3 cm to 60 cm.
  const int n_rect = static_cast<int>(area_m2 * 7);
  for (int i = 0; i < n_rect; ++i) {
    const double w = logUniform(0.03, 0.6) * tpm, h = w * logUniform(0.35, 2.8);
    const double ang = rng.uniform(0.0, 1.0) < 0.6 ? 0.0 : rng.uniform(0.0, 90.0);
    cv::RotatedRect rr(pt(), cv::Size2f((float)w, (float)h), (float)ang);
    cv::Point2f p[4];
    rr.points(p);
    std::vector<cv::Point> poly;
    for (auto& q : p) poly.emplace_back(cvRound(q.x), cvRound(q.y));
    if (rng.uniform(0.0, 1.0) < 0.75)
      cv::fillConvexPoly(img, poly, gray(), cv::LINE_AA);
    else
      cv::polylines(img, poly, true, gray(), std::max(2, (int)(rng.uniform(0.006, 0.02) * tpm)), cv::LINE_AA);
  }
  // Blobs (ellipses) from 2 cm to 25 cm.
  const int n_blob = static_cast<int>(area_m2 * 3);
  for (int i = 0; i < n_blob; ++i) {
    const double r = logUniform(0.02, 0.25) * tpm;
    cv::ellipse(img, cv::RotatedRect(pt(), cv::Size2f((float)(2 * r), (float)(2 * r * rng.uniform(0.4, 1.0))),
                                     rng.uniform(0.f, 180.f)),
                gray(), cv::FILLED, cv::LINE_AA);
  }
  // Checker patches (3..7 squares a side, 3 to 12 cm squares).
  const int n_check = std::max(1, static_cast<int>(area_m2 * 0.4));
  for (int i = 0; i < n_check; ++i) {
    const int sq = std::max(3, (int)(rng.uniform(0.03, 0.12) * tpm));
    const int n = rng.uniform(3, 8);
    const cv::Point2f o = pt();
    const cv::Scalar a = gray(), b = cv::Scalar(255) - a;
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c)
        cv::rectangle(img, cv::Rect((int)o.x + c * sq, (int)o.y + r * sq, sq, sq), ((r + c) & 1) ? a : b, cv::FILLED);
  }
  // A few thick lines (long straight edges, T-junctions with the rectangles).
  const int n_line = static_cast<int>(area_m2 * 0.6);
  for (int i = 0; i < n_line; ++i) {
    const cv::Point2f a = pt();
    const double len = logUniform(0.15, 1.2) * tpm, ang = rng.uniform(0.0, 2 * M_PI);
    const cv::Point2f b(a.x + (float)(len * std::cos(ang)), a.y + (float)(len * std::sin(ang)));
    cv::line(img, a, b, gray(), std::max(2, (int)(rng.uniform(0.01, 0.04) * tpm)), cv::LINE_AA);
  }

  // Fine grain over everything (surfaces are never perfectly flat-coloured), then keep albedo in [0.06, 0.94].
  cv::Mat grain(height / 4, width / 4, CV_32F), grain_up, f;
  rng.fill(grain, cv::RNG::UNIFORM, -12.0, 12.0);
  cv::resize(grain, grain_up, img.size(), 0, 0, cv::INTER_LINEAR);
  img.convertTo(f, CV_32F);
  f += grain_up;
  f.convertTo(img, CV_8U, 0.88, 0.06 * 255.0);
  return img;
}

namespace {

/// Pastes a grayscale photo (scaled to `width_m` meters) into `tex` with its top-left at (u, v) meters.
bool pastePoster(const std::string& path, double u_m, double v_m, double width_m, double tpm, cv::Mat* tex) {
  cv::Mat photo = codecs::imread(path, cv::IMREAD_GRAYSCALE);
  if (photo.empty()) return false;
  const int w = static_cast<int>(width_m * tpm);
  const int h = static_cast<int>(w * static_cast<double>(photo.rows) / photo.cols);
  cv::Mat scaled;
  cv::resize(photo, scaled, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  cv::Rect roi(static_cast<int>(u_m * tpm), static_cast<int>(v_m * tpm), w, h);
  roi &= cv::Rect(0, 0, tex->cols, tex->rows);
  if (roi.area() <= 0) return false;
  // A dark 1.5 cm frame around the poster: strong corners.
  const int b = std::max(2, static_cast<int>(0.015 * tpm));
  cv::rectangle(*tex, cv::Rect(roi.x - b, roi.y - b, roi.width + 2 * b, roi.height + 2 * b), cv::Scalar(25), cv::FILLED);
  scaled(cv::Rect(0, 0, roi.width, roi.height)).convertTo((*tex)(roi), CV_8U, 0.85, 0.06 * 255);
  return true;
}

int nextPow2(double v) {
  int p = 1;
  while (p < v) p <<= 1;
  return p;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Scene

Scene::Scene(const SceneParams& params, std::vector<SceneTexture> textures, std::vector<SceneBox> boxes)
    : params_(params), textures_(std::move(textures)), boxes_(std::move(boxes)) {
  if (!(params.room_x > 0 && params.room_y > 0 && params.room_z > 0))
    throw std::invalid_argument("Scene: room_x, room_y and room_z must be > 0");
  if (textures_.size() < 6) throw std::invalid_argument("Scene: needs at least 6 textures (room faces)");
  if (!(params.light_range_m > 0)) throw std::invalid_argument("Scene: light_range_m must be > 0");
  for (const auto& b : boxes_)
    if (b.texture < 0 || b.texture >= static_cast<int>(textures_.size()) || !(b.lo.array() < b.hi.array()).all())
      throw std::invalid_argument("Scene: box with a bad texture index or lo >= hi");
  room_lo_ = Eigen::Vector3f(-params.room_x / 2, -params.room_y / 2, 0.f);
  room_hi_ = Eigen::Vector3f(params.room_x / 2, params.room_y / 2, params.room_z);
  light_ = Eigen::Vector3f(params.light_x, params.light_y, params.light_z);
}

std::vector<cv::Mat> makeRoomAlbedo(const SceneParams& p, double poster_top_m, int* posters_out) {
  const double tpm = p.texels_per_m;
  const int wx = nextPow2(p.room_x * tpm), wy = nextPow2(p.room_y * tpm), wz = nextPow2(p.room_z * tpm);
  // Room faces: 0/1 walls at x = -/+ (u along y, v down), 2/3 walls at y = -/+ (u along x), 4 floor, 5 ceiling.
  std::vector<cv::Mat> albedo = {
      makeProceduralTexture(wy, wz, tpm, p.seed * 16 + 0), makeProceduralTexture(wy, wz, tpm, p.seed * 16 + 1),
      makeProceduralTexture(wx, wz, tpm, p.seed * 16 + 2), makeProceduralTexture(wx, wz, tpm, p.seed * 16 + 3),
      makeProceduralTexture(wx, wy, tpm, p.seed * 16 + 4), makeProceduralTexture(wx, wy, tpm, p.seed * 16 + 5)};
  int posters = 0;
  if (!p.photo_dir.empty()) {
    // Real photos from Debian's opencv-doc (if installed): two per wall.
    const char* names[] = {"graf1.png", "leuvenA.jpg", "building.jpg", "home.jpg", "box_in_scene.png", "left01.jpg",
                           "sudoku.png", "stuff.jpg", "aero1.jpg", "board.jpg", "starry_night.jpg", "fruits.jpg"};
    cv::RNG rng(p.seed * 7919 + 3);
    int k = 0;
    for (int face = 0; face < 4; ++face) {
      const double len = face < 2 ? p.room_y : p.room_x;
      for (int j = 0; j < 2; ++j, ++k) {
        const std::string path = p.photo_dir + "/" + names[k % 12];
        if (!fileExists(path)) continue;
        const double width_m = rng.uniform(0.7, 1.2);
        const double u = (j + 0.5) * len / 2 - width_m / 2 + rng.uniform(-0.3, 0.3);
        const double v = p.room_z - poster_top_m - rng.uniform(0.0, 0.4);  // top edge above the floor
        if (pastePoster(path, std::max(0.1, u), std::max(0.05, v), width_m, tpm, &albedo[face])) ++posters;
      }
    }
  }
  const int box_tex = static_cast<int>(nextPow2(2.0 * tpm));
  for (int i = 0; i < 4; ++i) albedo.push_back(makeProceduralTexture(box_tex, box_tex, tpm, p.seed * 16 + 6 + i));
  if (posters_out) *posters_out = posters;
  return albedo;
}

Scene Scene::makeDefaultRoom(const SceneParams& p) {
  int posters = 0;
  const std::vector<cv::Mat> albedo = makeRoomAlbedo(p, 1.9, &posters);  // top edge 1.9-2.3 m above the floor
  std::vector<SceneTexture> tex;
  for (const auto& a : albedo) tex.emplace_back(a, static_cast<float>(p.texels_per_m));

  // Boxes and pillars at several depths, >= 1 m away from the default trajectory (|x| <= 1.35, |y| <= 0.9).
  const float hx = p.room_x / 2, hy = p.room_y / 2, hz = p.room_z;
  auto box = [](float cx, float cy, float sx, float sy, float z0, float z1, int t) {
    return SceneBox{Eigen::Vector3f(cx - sx / 2, cy - sy / 2, z0), Eigen::Vector3f(cx + sx / 2, cy + sy / 2, z1), t};
  };
  std::vector<SceneBox> boxes = {
      box(0.72f * hx, 0.63f * hy, 0.9f, 0.9f, 0.f, 1.1f, 6),         // crate
      box(0.72f * hx, 0.63f * hy, 0.45f, 0.45f, 1.1f, 1.5f, 7),      // small crate on top
      box(-0.68f * hx, -0.63f * hy, 0.5f, 0.5f, 0.f, hz, 8),         // pillar
      box(-0.70f * hx, 0.67f * hy, 1.2f, 0.7f, 0.f, 0.8f, 9),        // low box
      box(0.65f * hx, -0.70f * hy, 0.4f, 0.4f, 0.f, hz, 7),          // thin pillar
      box(0.05f * hx, 0.85f * hy, 1.6f, 0.45f, 0.f, 1.8f, 6),        // shelf against the +y wall
      box(-0.12f * hx, -0.80f * hy, 0.8f, 0.8f, 0.f, 0.6f, 9),       // low crate near the -y wall
      box(0.82f * hx, 0.0f, 0.5f, 1.2f, 0.75f * hz, hz, 8),          // duct hanging from the ceiling
  };
  Scene s(p, std::move(tex), std::move(boxes));
  s.photo_posters_ = posters;
  return s;
}

}  // namespace iraf_vo
