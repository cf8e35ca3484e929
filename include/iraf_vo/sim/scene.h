// Textured 3D scene of the simulator: the inside of a room (axis-aligned box, z up, floor at z = 0)
// plus axis-aligned boxes/pillars standing in it. Rays are intersected analytically (slab test), the
// surface texture is sampled with trilinear mipmapping (level chosen from the pixel footprint), and a
// smooth Lambertian shading from a ceiling light is applied. ROS-free.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace iraf_vo {

/// Albedo texture (CV_8UC1, power-of-two sides, wraps around) with its mip pyramid.
class SceneTexture {
 public:
  SceneTexture() = default;
  /// `albedo` must be CV_8UC1 with power-of-two width and height; `texels_per_m` maps meters to texels.
  SceneTexture(const cv::Mat& albedo, float texels_per_m);

  /// Trilinear sample in [0,1] at surface coordinates (u, v) in meters; `footprint_texels` is the
  /// size of the pixel's footprint on the surface in level-0 texels (selects the mip level).
  float sample(float u_m, float v_m, float footprint_texels) const;
  /// Bilinear sample of one mip level (level clamped to the pyramid).
  float sampleLevel(float u_m, float v_m, int level) const;

  float texelsPerMeter() const { return texels_per_m_; }
  int levels() const { return static_cast<int>(levels_.size()); }
  const cv::Mat& level(int i) const { return levels_[i]; }
  bool empty() const { return levels_.empty(); }

 private:
  std::vector<cv::Mat> levels_;
  float texels_per_m_ = 256.f;
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
  bool castRay(const Eigen::Vector3f& o, const Eigen::Vector3f& d, SceneHit* hit) const;

  /// Shaded radiance in [0, ~1] of a hit: albedo(u, v) * (ambient + Lambert(ceiling light)).
  float shade(const SceneHit& hit, float footprint_texels) const;

  const SceneParams& params() const { return params_; }
  const std::vector<SceneBox>& boxes() const { return boxes_; }
  const std::vector<SceneTexture>& textures() const { return textures_; }
  Eigen::Vector3f roomLo() const { return room_lo_; }
  Eigen::Vector3f roomHi() const { return room_hi_; }
  /// Number of photo posters pasted (0 when the photo folder is absent: procedural only).
  int photoPosters() const { return photo_posters_; }

 private:
  SceneParams params_;
  std::vector<SceneTexture> textures_;
  std::vector<SceneBox> boxes_;
  Eigen::Vector3f room_lo_ = Eigen::Vector3f::Zero(), room_hi_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f light_ = Eigen::Vector3f::Zero();
  int photo_posters_ = 0;
};

/// Procedural albedo (CV_8UC1, w x h, power-of-two sides) with corners at several scales: multi-scale
/// value noise + random rectangles, blobs, lines and checker patches. Deterministic for a seed.
cv::Mat makeProceduralTexture(int width, int height, double texels_per_m, uint64_t seed);

}  // namespace iraf_vo
