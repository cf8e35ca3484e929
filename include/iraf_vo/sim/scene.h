// Textured 3D scene of the simulator: the inside of a room (axis-aligned box, z up, floor at z = 0)
// plus axis-aligned boxes/pillars standing in it. Rays are intersected analytically (slab test), the
// surface texture is sampled with mipmapping (level chosen from the pixel footprint; two levels blended
// around LOD mid-steps), and a smooth Lambertian shading from a ceiling light is applied. ROS-free.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace iraf_vo {

/// Albedo texture (CV_8UC1, power-of-two sides, wraps around) with its mip pyramid.
class SceneTexture {
 public:
  SceneTexture() = default;
  /// `albedo` must be CV_8UC1 with power-of-two width and height; `texels_per_m` maps meters to texels.
  SceneTexture(const cv::Mat& albedo, float texels_per_m);

  /// Mipmapped ("brilinear") sample in [0,1] at surface coordinates (u, v) in meters; `footprint_texels`
  /// is the size of the pixel's footprint on the surface in level-0 texels (selects the mip level).
  float sample(float u_m, float v_m, float footprint_texels) const;
  /// Bilinear sample of one mip level (level clamped to the pyramid).
  float sampleLevel(float u_m, float v_m, int level) const;
  /// Bilinear sample of level `level` (must exist) at precomputed texel indices (any int, wrapped) and
  /// fractions: the renderer computes the coordinates in vectorized loops.
  float fetch(int level, int x0, int y0, float fx, float fy) const;

  float texelsPerMeter() const { return texels_per_m_; }
  int levels() const { return static_cast<int>(levels_.size()); }
  const cv::Mat& level(int i) const { return levels_[i]; }
  bool empty() const { return levels_.empty(); }

 private:
  struct Level {  // raw view of levels_[i] for the inner loop
    const uint8_t* data;
    size_t step;
    int wmask, hmask;
    float scale;  // texels per meter at this level
  };
  std::vector<cv::Mat> levels_;
  std::vector<Level> view_;
  float texels_per_m_ = 256.f;
  float max_lod_ = 0.f;
};

struct SceneBox {
  Eigen::Vector3f lo, hi;  // world corners (m), lo < hi on every axis
  int texture = 0;         // index into Scene::textures
};

/// Result of a ray cast. `normal` faces the ray origin; (u, v) are surface coordinates in meters
/// (u to the viewer's right on vertical faces, v downwards).
struct SceneHit {
  float t = 0.f;            // distance along the (unit) ray direction
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  float u = 0.f, v = 0.f;
  int texture = -1;
  int surface = -1;         // 0..5: room faces (-x,+x,-y,+y,floor,ceiling); 6 + i: box i
};

struct SceneParams {
  // Room interior (m): x in [-room_x/2, room_x/2], y in [-room_y/2, room_y/2], z in [0, room_z].
  double room_x = 8.0;
  double room_y = 6.0;
  double room_z = 3.0;
  double texels_per_m = 256.0;  // texture resolution (256 -> 3.9 mm texels)
  // Folder with photos pasted as posters on the walls (Debian's opencv-doc examples); procedural
  // textures only when empty or absent.
  std::string photo_dir = "/usr/share/doc/opencv-doc/examples/data";
  uint64_t seed = 1;
  // Ceiling light (world position) and the ambient share of the shading.
  double light_x = 0.0, light_y = 0.0, light_z = 2.9;
  double ambient = 0.45;
  // Direct light falls off as 1 / (1 + d^2 / light_range_m^2) (a far light with a huge range = the sun).
  double light_range_m = 3.0;
  // > 0: the ceiling is an emissive sky, radiance = albedo * ceiling_shade (no Lambert term).
  double ceiling_shade = 0.0;
};

class Scene {
 public:
  /// The default room: 8 x 6 x 3 m, 6 textured faces, pillars/boxes at several depths.
  static Scene makeDefaultRoom(const SceneParams& params);
  /// Empty room with the given textures (tests): textures[0..5] for the 6 faces.
  Scene(const SceneParams& params, std::vector<SceneTexture> textures, std::vector<SceneBox> boxes);
  Scene() = default;

  /// Closest intersection of the ray o + t d (d unit, o inside the room) with any surface.
  /// Returns false when the ray leaves the room without a hit (origin outside) or d is not finite.
  /// `box_subset` (optional, `n_subset` indices) restricts the boxes tested (culling by the renderer).
  bool castRay(const Eigen::Vector3f& o, const Eigen::Vector3f& d, SceneHit* hit, const int* box_subset = nullptr,
               int n_subset = 0) const;

  /// Shaded radiance in [0, ~1] of a hit: albedo(u, v) * (ambient + Lambert(ceiling light)).
  float shade(const SceneHit& hit, float footprint_texels) const;

  const SceneParams& params() const { return params_; }
  const std::vector<SceneBox>& boxes() const { return boxes_; }
  const std::vector<SceneTexture>& textures() const { return textures_; }
  Eigen::Vector3f roomLo() const { return room_lo_; }
  Eigen::Vector3f roomHi() const { return room_hi_; }
  /// Number of photo posters pasted (0 when the photo folder is absent: procedural only).
  int photoPosters() const { return photo_posters_; }
  void setPhotoPosters(int n) { photo_posters_ = n; }

 private:
  SceneParams params_;
  std::vector<SceneTexture> textures_;
  std::vector<SceneBox> boxes_;
  Eigen::Vector3f room_lo_ = Eigen::Vector3f::Zero(), room_hi_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f light_ = Eigen::Vector3f::Zero();
  int photo_posters_ = 0;
};

/// Albedo of the 6 faces of the room params.room_x/y/z (procedural; 2 photo posters per wall with their top
/// edge poster_top_m .. poster_top_m + 0.4 m above the floor when params.photo_dir has them, *posters = how
/// many) followed by 4 procedural box textures (2 m, wrapping).
std::vector<cv::Mat> makeRoomAlbedo(const SceneParams& params, double poster_top_m, int* posters);

/// Procedural albedo (CV_8UC1, w x h, power-of-two sides) with corners at several scales: multi-scale
/// value noise + random rectangles, blobs, lines and checker patches. Deterministic for a seed.
cv::Mat makeProceduralTexture(int width, int height, double texels_per_m, uint64_t seed);


// ------------------------------------------------------------------------------------------------
// Hot path, inline (the renderer calls these once per ray).

namespace detail {
inline int fastFloor(float x) {
  const int i = static_cast<int>(x);
  return i - (x < static_cast<float>(i));
}
/// log2 for x >= 1: exponent + quadratic in the mantissa (exact at powers of two, continuous, error < 0.01).
inline float fastLog2(float x) {
  uint32_t bits;
  std::memcpy(&bits, &x, 4);
  const float e = static_cast<float>(static_cast<int>((bits >> 23) & 255) - 127);
  const uint32_t mb = (bits & 0x7fffffu) | 0x3f800000u;
  float m;
  std::memcpy(&m, &mb, 4);
  m -= 1.f;
  return e + m * (1.3465f - 0.3465f * m);
}
}  // namespace detail

inline float SceneTexture::sampleLevel(float u_m, float v_m, int level) const {
  level = std::max(0, std::min(level, static_cast<int>(view_.size()) - 1));
  const Level& m = view_[level];
  const float x = u_m * m.scale - 0.5f, y = v_m * m.scale - 0.5f;
  const int x0 = detail::fastFloor(x), y0 = detail::fastFloor(y);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const int xa = x0 & m.wmask, xb = (x0 + 1) & m.wmask;  // power of two: & wraps (also negative ints)
  const uint8_t* r0 = m.data + m.step * static_cast<size_t>(y0 & m.hmask);
  const uint8_t* r1 = m.data + m.step * static_cast<size_t>((y0 + 1) & m.hmask);
  const float top = r0[xa] + fx * (static_cast<float>(r0[xb]) - r0[xa]);
  const float bot = r1[xa] + fx * (static_cast<float>(r1[xb]) - r1[xa]);
  return (top + fy * (bot - top)) * (1.f / 255.f);
}

inline float SceneTexture::fetch(int level, int x0, int y0, float fx, float fy) const {
  const Level& m = view_[level];
  const int xa = x0 & m.wmask, xb = (x0 + 1) & m.wmask;
  const uint8_t* r0 = m.data + m.step * static_cast<size_t>(y0 & m.hmask);
  const uint8_t* r1 = m.data + m.step * static_cast<size_t>((y0 + 1) & m.hmask);
  const float top = r0[xa] + fx * (static_cast<float>(r0[xb]) - r0[xa]);
  const float bot = r1[xa] + fx * (static_cast<float>(r1[xb]) - r1[xa]);
  return (top + fy * (bot - top)) * (1.f / 255.f);
}

inline float SceneTexture::sample(float u_m, float v_m, float footprint_texels) const {
  if (!(footprint_texels > 1.f)) return sampleLevel(u_m, v_m, 0);
  const float lod = std::min(detail::fastLog2(footprint_texels), max_lod_);
  const int l0 = static_cast<int>(lod);
  // "Brilinear": blend two levels only for a fractional LOD in [0.3, 0.7] (remapped to [0, 1]), the
  // nearest level elsewhere; continuous in the LOD, fewer texture reads than trilinear. The renderer's
  // span path computes the same level/weight/coordinates in vectorized form (Renderer::renderSpan).
  const float f = std::min(1.f, std::max(0.f, 2.5f * (lod - static_cast<float>(l0)) - 0.75f));
  if (f <= 0.f) return sampleLevel(u_m, v_m, l0);
  if (f >= 1.f) return sampleLevel(u_m, v_m, l0 + 1);
  const float a = sampleLevel(u_m, v_m, l0);
  const float b = sampleLevel(u_m, v_m, l0 + 1);
  return a + f * (b - a);
}

inline bool Scene::castRay(const Eigen::Vector3f& o, const Eigen::Vector3f& d, SceneHit* hit, const int* box_subset,
                           int n_subset) const {
  if (!d.allFinite() || !o.allFinite()) return false;
  if ((o.array() <= room_lo_.array()).any() || (o.array() >= room_hi_.array()).any()) return false;
  // Exactly-zero components (axis-parallel rays) become tiny ones (+-1e-20, no change otherwise): no 0 * inf
  // below. Written without comparisons so that the renderer's span loop (same formula) vectorizes.
  const float dx0 = d.x() + std::copysign(1e-20f, d.x()), dy0 = d.y() + std::copysign(1e-20f, d.y()),
              dz0 = d.z() + std::copysign(1e-20f, d.z());
  const float ix = 1.f / dx0, iy = 1.f / dy0, iz = 1.f / dz0;
  // Room exit: the nearest of the three faces the ray points to.
  const float tx = ((dx0 > 0 ? room_hi_.x() : room_lo_.x()) - o.x()) * ix;
  const float ty = ((dy0 > 0 ? room_hi_.y() : room_lo_.y()) - o.y()) * iy;
  const float tz = ((dz0 > 0 ? room_hi_.z() : room_lo_.z()) - o.z()) * iz;
  float best = tx;
  int axis = 0;
  if (ty < best) best = ty, axis = 1;
  if (tz < best) best = tz, axis = 2;
  int surface = axis * 2 + ((axis == 0 ? dx0 : axis == 1 ? dy0 : dz0) > 0 ? 1 : 0);
  // Boxes: slab test, entry face = axis of the largest near-slab distance.
  const int nb = box_subset ? n_subset : static_cast<int>(boxes_.size());
  for (int j = 0; j < nb; ++j) {
    const int i = box_subset ? box_subset[j] : j;
    const SceneBox& b = boxes_[i];
    const float ax = (b.lo.x() - o.x()) * ix, bx = (b.hi.x() - o.x()) * ix;
    const float ay = (b.lo.y() - o.y()) * iy, by = (b.hi.y() - o.y()) * iy;
    const float az = (b.lo.z() - o.z()) * iz, bz = (b.hi.z() - o.z()) * iz;
    const float nx = std::min(ax, bx), ny = std::min(ay, by), nz = std::min(az, bz);
    const float fx = std::max(ax, bx), fy = std::max(ay, by), fz = std::max(az, bz);
    const float tn = std::max(nx, std::max(ny, nz));
    const float tf = std::min(fx, std::min(fy, fz));
    if (tn <= tf && tn > 1e-4f && tn < best) {
      best = tn;
      axis = (nx >= ny && nx >= nz) ? 0 : (ny >= nz ? 1 : 2);
      surface = 6 + i;
    }
  }
  if (!(best > 0.f) || !std::isfinite(best)) return false;
  hit->t = best;
  hit->point = o + best * d;
  hit->normal.setZero();
  const float dir_axis = axis == 0 ? dx0 : axis == 1 ? dy0 : dz0;
  const float n = dir_axis > 0 ? -1.f : 1.f;  // faces the ray origin
  hit->normal[axis] = n;
  const Eigen::Vector3f& p = hit->point;
  // (u, v): u = p . (up x n) on vertical faces (viewer's right), v = -z (down); floor/ceiling: (x, y).
  float u, v;
  if (axis == 0) u = n * p.y(), v = -p.z();
  else if (axis == 1) u = -n * p.x(), v = -p.z();
  else u = p.x(), v = n * p.y();
  if (surface < 6) {
    hit->texture = surface;
    // Room faces: shift so that the face covers [0, extent) of its texture (posters placed there).
    const Eigen::Vector3f ext = room_hi_ - room_lo_;
    if (axis == 0) u += ext.y() / 2, v += ext.z();
    else if (axis == 1) u += ext.x() / 2, v += ext.z();
    else u += ext.x() / 2, v += ext.y() / 2;
  } else {
    hit->texture = boxes_[surface - 6].texture;
    u += 0.37f * (surface + axis), v += 0.23f * (surface + 2 * axis);  // different patch per face
  }
  hit->u = u;
  hit->v = v;
  hit->surface = surface;
  return true;
}

inline float Scene::shade(const SceneHit& hit, float footprint_texels) const {
  const float albedo = textures_[hit.texture].sample(hit.u, hit.v, footprint_texels);
  const Eigen::Vector3f l = light_ - hit.point;
  const float d2 = l.squaredNorm();
  const float cosang = std::max(0.f, hit.normal.dot(l)) / std::sqrt(d2 + 1e-12f);
  const float r = static_cast<float>(params_.light_range_m);
  const float direct = std::min(1.f, cosang * 1.6f / (1.f + d2 / (r * r)));
  const float a = static_cast<float>(params_.ambient);
  if (hit.surface == 5 && params_.ceiling_shade > 0.0) return albedo * static_cast<float>(params_.ceiling_shade);
  return albedo * (a + (1.f - a) * direct);
}

}  // namespace iraf_vo
