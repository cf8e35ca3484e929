#include "iraf_vo/sim/renderer.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <opencv2/core/utility.hpp>

namespace iraf_vo {

std::string validate(const SimParams& p) {
  std::ostringstream err;
  if (p.frames < 1) err << "frames must be >= 1 (got " << p.frames << "); ";
  if (!(p.rate_hz > 0.0)) err << "rate_hz must be > 0; ";
  if (p.supersample < 1 || p.supersample > 4) err << "supersample must be in [1, 4] (got " << p.supersample << "); ";
  if (p.threads < 0) err << "threads must be >= 0; ";
  if (!(p.brightness > 0.0)) err << "brightness must be > 0; ";
  if (p.motion_blur_samples < 1) err << "motion_blur_samples must be >= 1; ";
  if (!(p.exposure_time_s >= 0.0)) err << "exposure_time_s must be >= 0; ";
  if (p.width < 0 || p.height < 0) err << "width/height must be >= 0; ";
  return err.str();
}

Renderer::Renderer(CameraModelPtr camera, std::shared_ptr<const Scene> scene, const SimParams& params)
    : camera_(std::move(camera)), scene_(std::move(scene)), params_(params) {
  if (!camera_) throw std::invalid_argument("Renderer: null camera model");
  if (!scene_) throw std::invalid_argument("Renderer: null scene");
  const std::string err = validate(params);
  if (!err.empty()) throw std::invalid_argument("Renderer: " + err);
  w_ = camera_->width();
  h_ = camera_->height();
  if (w_ < 2 || h_ < 2) throw std::invalid_argument("Renderer: camera resolution must be at least 2x2");
  ss_ = params.supersample;
  const size_t n = static_cast<size_t>(w_) * h_ * ss_ * ss_;
  // + kTile padding: the span renderer reads whole 16-pixel spans past the last pixel.
  bx_.assign(n + kTile, 0.f), by_.assign(n + kTile, 0.f), bz_.assign(n + kTile, 1.f), valid_.assign(n + kTile, 0);
  footprint_.assign(static_cast<size_t>(w_) * h_ + kTile, 0.f);
  size_t k = 0;
  for (int r = 0; r < h_; ++r)
    for (int c = 0; c < w_; ++c)
      for (int sy = 0; sy < ss_; ++sy)
        for (int sx = 0; sx < ss_; ++sx, ++k) {
          const Eigen::Vector2d uv(c + (sx + 0.5) / ss_ - 0.5, r + (sy + 0.5) / ss_ - 0.5);
          Eigen::Vector3d b;
          if (camera_->unproject(uv, &b) && b.allFinite() && b.norm() > 0.5) {
            b.normalize();
            bx_[k] = static_cast<float>(b.x()), by_[k] = static_cast<float>(b.y()), bz_[k] = static_cast<float>(b.z());
            valid_[k] = 1;
          }
        }
  // Angular size of a pixel (distance between neighbouring pixel-centre bearings); a sub-sample
  // covers 1/ss of it.
  auto centre = [&](int c, int r, Eigen::Vector3d* b) {
    return camera_->unproject(Eigen::Vector2d(c, r), b) && b->allFinite();
  };
  for (int r = 0; r < h_; ++r)
    for (int c = 0; c < w_; ++c) {
      Eigen::Vector3d b0, bu, bv;
      if (!centre(c, r, &b0)) continue;
      const int cn = c + 1 < w_ ? c + 1 : c - 1, rn = r + 1 < h_ ? r + 1 : r - 1;
      double a = 0.0;
      if (centre(cn, r, &bu)) a = std::max(a, std::acos(std::min(1.0, b0.normalized().dot(bu.normalized()))));
      if (centre(c, rn, &bv)) a = std::max(a, std::acos(std::min(1.0, b0.normalized().dot(bv.normalized()))));
      footprint_[static_cast<size_t>(r) * w_ + c] = static_cast<float>(a / ss_);
    }
  // LOD bound valid for every texture (levels l0 and l0 + 1 must exist).
  int levels = 64;
  for (const SceneTexture& t : scene_->textures()) levels = std::min(levels, t.levels());
  max_lod_ = static_cast<float>(std::max(0, levels - 1)) - 1e-3f;
  if (levels < 2) max_lod_ = 0.f;
  // Tile cones for box culling.
  tiles_x_ = (w_ + kTile - 1) / kTile, tiles_y_ = (h_ + kTile - 1) / kTile;
  tile_axis_.assign(static_cast<size_t>(tiles_x_) * tiles_y_, Eigen::Vector3f::UnitZ());
  tile_half_angle_.assign(tile_axis_.size(), static_cast<float>(M_PI));
  for (int ty = 0; ty < tiles_y_; ++ty)
    for (int tx = 0; tx < tiles_x_; ++tx) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      std::vector<Eigen::Vector3d> rays;
      for (int r = ty * kTile; r < std::min(h_, (ty + 1) * kTile); ++r)
        for (int c = tx * kTile; c < std::min(w_, (tx + 1) * kTile); ++c)
          for (int s = 0; s < ss_ * ss_; ++s) {
            const size_t k = (static_cast<size_t>(r) * w_ + c) * ss_ * ss_ + s;
            if (!valid_[k]) continue;
            rays.emplace_back(bx_[k], by_[k], bz_[k]);
            sum += rays.back();
          }
      const size_t t = static_cast<size_t>(ty) * tiles_x_ + tx;
      if (rays.empty() || sum.norm() < 1e-6) continue;  // keep the conservative half-angle pi
      const Eigen::Vector3d axis = sum.normalized();
      double max_angle = 0.0;
      for (const auto& b : rays) max_angle = std::max(max_angle, std::acos(std::min(1.0, axis.dot(b))));
      tile_axis_[t] = axis.cast<float>();
      tile_half_angle_[t] = static_cast<float>(max_angle + 1e-4);
    }
}

int64_t Renderer::frameStampNs(int frame) const {
  return params_.start_ns + static_cast<int64_t>(std::llround(frame * 1e9 / params_.rate_hz));
}

void Renderer::renderTileRows(const Eigen::Isometry3d& T_W_C, int tr0, int tr1, cv::Mat* radiance,
                              cv::Mat* depth) const {
  const Eigen::Matrix3f R = T_W_C.linear().cast<float>();
  const Eigen::Vector3f o = T_W_C.translation().cast<float>();
  const float scale = static_cast<float>(255.0 * params_.brightness);
  const float tpm = static_cast<float>(scene_->params().texels_per_m);
  const int nsub = ss_ * ss_;
  const float inv_nsub = 1.f / nsub;
  const Scene& scene = *scene_;
  const std::vector<SceneBox>& boxes = scene.boxes();
  // Bounding spheres of the boxes relative to the camera centre.
  std::vector<Eigen::Vector3f> centre(boxes.size());
  std::vector<float> dist(boxes.size()), radius(boxes.size());
  for (size_t b = 0; b < boxes.size(); ++b) {
    centre[b] = 0.5f * (boxes[b].lo + boxes[b].hi) - o;
    dist[b] = centre[b].norm();
    radius[b] = 0.5f * (boxes[b].hi - boxes[b].lo).norm() + 1e-3f;
  }
  std::vector<int> cand(boxes.size());
  SceneHit hit;
  for (int ty = tr0; ty < tr1; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      const int tile = ty * tiles_x_ + tx;
      const Eigen::Vector3f axis = R * tile_axis_[tile];
      int nc = 0;
      for (size_t b = 0; b < boxes.size(); ++b) {
        if (dist[b] <= radius[b]) {
          cand[nc++] = static_cast<int>(b);
          continue;
        }
        const float cosb = std::max(-1.f, std::min(1.f, centre[b].dot(axis) / dist[b]));
        if (std::acos(cosb) <= tile_half_angle_[tile] + std::asin(radius[b] / dist[b])) cand[nc++] = static_cast<int>(b);
      }
      const int r_end = std::min(h_, (ty + 1) * kTile), c_end = std::min(w_, (tx + 1) * kTile);
      if (nsub == 1 && params_.span_renderer) {
        for (int r = ty * kTile; r < r_end; ++r)
          renderSpan(R, o, r, tx * kTile, c_end - tx * kTile, cand.data(), nc, radiance->ptr<float>(r),
                     depth ? depth->ptr<float>(r) : nullptr);
        continue;
      }
      for (int r = ty * kTile; r < r_end; ++r) {
        float* out = radiance->ptr<float>(r);
        float* dep = depth ? depth->ptr<float>(r) : nullptr;
        for (int c = tx * kTile; c < c_end; ++c) {
          const size_t pix = static_cast<size_t>(r) * w_ + c;
          const float fp_ang = footprint_[pix] * tpm;
          float acc = 0.f;
          for (int s = 0; s < nsub; ++s) {
            const size_t k = pix * nsub + s;
            if (!valid_[k]) continue;
            const Eigen::Vector3f b(bx_[k], by_[k], bz_[k]);
            const Eigen::Vector3f d = R * b;
            if (!scene.castRay(o, d, &hit, cand.data(), nc)) continue;
            // Footprint on the surface in texels: t * pixel angle / sqrt(cos incidence) (a compromise
            // between blur and aliasing at grazing angles).
            const float cosi = std::max(0.05f, std::abs(hit.normal.dot(d)));
            acc += scene.shade(hit, hit.t * fp_ang / std::sqrt(cosi));
            if (dep && s == 0 && nsub == 1) dep[c] = hit.t * b.z();
          }
          out[c] = acc * inv_nsub * scale;
          if (dep && nsub > 1) {
            // z-depth of the pixel centre ray.
            Eigen::Vector3d p;
            double z = 0.0;
            dep[c] = castPixel(T_W_C, Eigen::Vector2d(c, r), &p, &z) ? static_cast<float>(z) : 0.f;
          }
        }
      }
    }
  }
}

namespace {
/// 1/sqrt(x) for x > 0: bit-trick estimate + 3 Newton steps (relative error ~1e-7). Pure arithmetic, so
/// the span loops vectorize without -fno-math-errno.
inline float rsqrt(float x) {
  uint32_t i = __builtin_bit_cast(uint32_t, x);
  i = 0x5f375a86u - (i >> 1);
  float y = __builtin_bit_cast(float, i);
  const float hx = 0.5f * x;
  y = y * (1.5f - hx * y * y);
  y = y * (1.5f - hx * y * y);
  y = y * (1.5f - hx * y * y);
  return y;
}
}  // namespace

void Renderer::renderSpan(const Eigen::Matrix3f& R, const Eigen::Vector3f& o, int r, int c0, int n, const int* cand,
                          int nc, float* out, float* dep) const {
  // Same computation as Scene::castRay + Scene::shade, written as branch-free loops over up to kTile
  // pixels in structure-of-arrays form so that the compiler vectorizes everything but the texture reads.
  constexpr int N = kTile;
  alignas(64) float dx[N], dy[N], dz[N], ix[N], iy[N], iz[N], t[N], shade[N], bz[N];
  alignas(64) float fx0[N], fy0[N], fx1[N], fy1[N], wb[N];  // texel fractions (levels l0, l0+1), level blend
  alignas(64) int xi0[N], yi0[N], xi1[N], yi1[N], lv[N];     // texel indices (offset by kOff), level l0
  alignas(64) int axis[N], surf[N];
  const Scene& scene = *scene_;
  const Eigen::Vector3f lo = scene.roomLo(), hi = scene.roomHi(), ext = hi - lo;
  const float ox = o.x(), oy = o.y(), oz = o.z();
  const float lox = lo.x(), loy = lo.y(), loz = lo.z(), hix = hi.x(), hiy = hi.y(), hiz = hi.z();
  const size_t p0 = static_cast<size_t>(r) * w_ + c0;
  const float* __restrict bxp = bx_.data() + p0;
  const float* __restrict byp = by_.data() + p0;
  const float* __restrict bzp = bz_.data() + p0;
  const float r00 = R(0, 0), r01 = R(0, 1), r02 = R(0, 2), r10 = R(1, 0), r11 = R(1, 1), r12 = R(1, 2), r20 = R(2, 0),
              r21 = R(2, 1), r22 = R(2, 2);
  // Pass 1: world directions, room exit (nearest of the three faces the ray points to).
  for (int i = 0; i < N; ++i) {
    const float b0 = bxp[i], b1 = byp[i], b2 = bzp[i];  // arrays padded by kTile: no bounds branch
    float x = r00 * b0 + r01 * b1 + r02 * b2, y = r10 * b0 + r11 * b1 + r12 * b2, z = r20 * b0 + r21 * b1 + r22 * b2;
    x += std::copysign(1e-20f, x), y += std::copysign(1e-20f, y), z += std::copysign(1e-20f, z);  // as castRay
    dx[i] = x, dy[i] = y, dz[i] = z, bz[i] = b2;
    ix[i] = 1.f / x, iy[i] = 1.f / y, iz[i] = 1.f / z;
    const float tx = ((x > 0 ? hix : lox) - ox) * ix[i];
    const float tyy = ((y > 0 ? hiy : loy) - oy) * iy[i];
    const float tz = ((z > 0 ? hiz : loz) - oz) * iz[i];
    const bool ay = tyy < tx;
    float best = ay ? tyy : tx;
    int a = ay ? 1 : 0;
    const bool az = tz < best;
    best = az ? tz : best;
    a = az ? 2 : a;
    const float da = a == 0 ? x : (a == 1 ? y : z);
    t[i] = best, axis[i] = a, surf[i] = a * 2 + (da > 0 ? 1 : 0);
  }
  // Pass 2: candidate boxes (slab test; entry face = axis of the largest near-slab distance).
  const std::vector<SceneBox>& boxes = scene.boxes();
  for (int j = 0; j < nc; ++j) {
    const SceneBox& b = boxes[cand[j]];
    const float lx = b.lo.x() - ox, ly = b.lo.y() - oy, lz = b.lo.z() - oz;
    const float hx = b.hi.x() - ox, hy = b.hi.y() - oy, hz = b.hi.z() - oz;
    const int sid = 6 + cand[j];
    for (int i = 0; i < N; ++i) {
      const float ax = lx * ix[i], bx = hx * ix[i], ay = ly * iy[i], by = hy * iy[i], az = lz * iz[i], bzz = hz * iz[i];
      const float nx = std::min(ax, bx), ny = std::min(ay, by), nz = std::min(az, bzz);
      const float fx = std::max(ax, bx), fy = std::max(ay, by), fz = std::max(az, bzz);
      const float tn = std::max(nx, std::max(ny, nz));
      const float tf = std::min(fx, std::min(fy, fz));
      const bool hit = (tn <= tf) & (tn > 1e-4f) & (tn < t[i]);
      const int a = ((nx >= ny) & (nx >= nz)) ? 0 : (ny >= nz ? 1 : 2);
      t[i] = hit ? tn : t[i];
      axis[i] = hit ? a : axis[i];
      surf[i] = hit ? sid : surf[i];
    }
  }
  // Pass 3: hit point, surface coordinates, Lambertian shading, footprint in texels.
  const SceneParams& sp = scene.params();
  const float lx = sp.light_x, ly = sp.light_y, lz = sp.light_z, amb = sp.ambient;
  const float inv_range2 = static_cast<float>(1.0 / (sp.light_range_m * sp.light_range_m));
  const float sky_on = sp.ceiling_shade > 0.0 ? 1.f : 0.f, sky_shade = static_cast<float>(sp.ceiling_shade);
  const float tpm = sp.texels_per_m;
  const float* __restrict fpp = footprint_.data() + p0;
  const float uo_x = 0.5f * ext.y(), uo_y = 0.5f * ext.x(), vo_wall = ext.z(), vo_floor = 0.5f * ext.y();
  const float max_lod = max_lod_;
  constexpr float kOff = 16384.f;
  for (int i = 0; i < N; ++i) {
    // Face selection by 0/1 weights and min/max written with fabs/copysign: no comparisons, so the loop
    // vectorizes under the default -ftrapping-math.
    const int a = axis[i];  // 0, 1, 2 -> weights by integer arithmetic
    const float e0 = static_cast<float>(((a - 1) * (a - 2)) >> 1), e1 = static_cast<float>(a * (2 - a)),
                e2 = 1.f - e0 - e1;
    const float af = e1 + 2.f * e2;
    const float tt = t[i];
    const float px = ox + tt * dx[i], py = oy + tt * dy[i], pz = oz + tt * dz[i];
    const float da = e0 * dx[i] + e1 * dy[i] + e2 * dz[i];
    const float nsgn = -std::copysign(1.f, da);  // normal faces the ray origin (da != 0)
    // u = p . (up x n) on walls, x on floor/ceiling; v = -z on walls, n * y on floor/ceiling.
    float uu = e0 * nsgn * py - e1 * nsgn * px + e2 * px;
    float vv = e2 * nsgn * py - (1.f - e2) * pz;
    const float room = static_cast<float>(((5 - surf[i]) >> 31) + 1);  // 1 for room faces (surf < 6)
    const float sf = static_cast<float>(surf[i]);
    uu += room * (e0 * uo_x + (1.f - e0) * uo_y) + (1.f - room) * 0.37f * (sf + af);
    vv += room * (e2 * vo_floor + (1.f - e2) * vo_wall) + (1.f - room) * 0.23f * (sf + 2.f * af);
    const float Lx = lx - px, Ly = ly - py, Lz = lz - pz;
    const float d2 = Lx * Lx + Ly * Ly + Lz * Lz;
    const float ndotl = nsgn * (e0 * Lx + e1 * Ly + e2 * Lz);
    const float cosang = 0.5f * (ndotl + std::fabs(ndotl)) * rsqrt(d2 + 1e-12f);  // max(0, n.l) / |l|
    const float lin = cosang * 1.6f / (1.f + d2 * inv_range2);
    const float direct = 0.5f * (lin + 1.f - std::fabs(lin - 1.f));  // min(1, lin)
    const float sky = sky_on * static_cast<float>(surf[i] == 5);      // emissive ceiling (int compare)
    shade[i] = amb + (1.f - amb) * direct + sky * (sky_shade - amb - (1.f - amb) * direct);
    const float ada = std::fabs(da);
    const float cosi = 0.5f * (ada + 0.05f + std::fabs(ada - 0.05f));  // max(0.05, |da|)
    const float fpt = tt * fpp[i] * tpm * rsqrt(cosi);  // footprint in level-0 texels
    // Mip level (as SceneTexture::sample, comparison-free): lod = log2(max(1, fp)) clamped to max_lod_,
    // "brilinear" blend weight of level l0 + 1, texel coordinates of both levels. kOff (a multiple of
    // every texture size) keeps coordinates positive so that truncation is floor; 1/512-texel precision.
    const float f1 = 0.5f * (fpt + 1.f + std::fabs(fpt - 1.f));
    const float lod0 = detail::fastLog2(f1);
    const float lod = 0.5f * (lod0 + max_lod - std::fabs(lod0 - max_lod));
    const int l0 = static_cast<int>(lod);
    const float fr = 2.5f * (lod - static_cast<float>(l0)) - 0.75f;
    const float fr1 = 0.5f * (fr + 1.f - std::fabs(fr - 1.f));
    wb[i] = 0.5f * (fr1 + std::fabs(fr1));
    lv[i] = l0;
    const float s0 = tpm * __builtin_bit_cast(float, (127 - l0) << 23);  // tpm / 2^l0
    const float x0 = uu * s0 - 0.5f + kOff, y0 = vv * s0 - 0.5f + kOff;
    const float x1 = uu * (0.5f * s0) - 0.5f + kOff, y1 = vv * (0.5f * s0) - 0.5f + kOff;
    xi0[i] = static_cast<int>(x0), yi0[i] = static_cast<int>(y0), xi1[i] = static_cast<int>(x1), yi1[i] = static_cast<int>(y1);
    fx0[i] = x0 - static_cast<float>(xi0[i]), fy0[i] = y0 - static_cast<float>(yi0[i]);
    fx1[i] = x1 - static_cast<float>(xi1[i]), fy1[i] = y1 - static_cast<float>(yi1[i]);
  }
  // Pass 4: texture reads (gathers), output.
  const float scale = static_cast<float>(255.0 * params_.brightness);
  const std::vector<SceneTexture>& tex = scene.textures();
  const uint8_t* valid = valid_.data() + p0;
  for (int i = 0; i < n; ++i) {
    const bool ok = valid[i] && t[i] > 0.f && std::isfinite(t[i]);
    const int s = surf[i];
    const int ti = s < 6 ? s : boxes[s - 6].texture;
    if (!ok) {
      out[c0 + i] = 0.f;
      if (dep) dep[c0 + i] = 0.f;
      continue;
    }
    const SceneTexture& tx = tex[ti];
    float albedo;
    if (wb[i] <= 0.f) {
      albedo = tx.fetch(lv[i], xi0[i], yi0[i], fx0[i], fy0[i]);
    } else if (wb[i] >= 1.f) {
      albedo = tx.fetch(lv[i] + 1, xi1[i], yi1[i], fx1[i], fy1[i]);
    } else {
      const float a = tx.fetch(lv[i], xi0[i], yi0[i], fx0[i], fy0[i]);
      albedo = a + wb[i] * (tx.fetch(lv[i] + 1, xi1[i], yi1[i], fx1[i], fy1[i]) - a);
    }
    out[c0 + i] = albedo * shade[i] * scale;
    if (dep) dep[c0 + i] = t[i] * bz[i];
  }
}

void Renderer::render(const Eigen::Isometry3d& T_W_C, cv::Mat* radiance, cv::Mat* depth) const {
  radiance->create(h_, w_, CV_32FC1);
  if (depth) {
    depth->create(h_, w_, CV_32FC1);
    depth->setTo(0.f);
  }
  // A pose that is not finite or outside the room sees nothing (as Scene::castRay): black image.
  const Eigen::Vector3f o = T_W_C.translation().cast<float>();
  if (!T_W_C.matrix().allFinite() || (o.array() <= scene_->roomLo().array()).any() ||
      (o.array() >= scene_->roomHi().array()).any()) {
    radiance->setTo(0.f);
    return;
  }
  if (params_.threads == 1) {
    renderTileRows(T_W_C, 0, tiles_y_, radiance, depth);
    return;
  }
  cv::parallel_for_(cv::Range(0, tiles_y_), [&](const cv::Range& range) {
    renderTileRows(T_W_C, range.start, range.end, radiance, depth);
  }, tiles_y_);
}

void Renderer::renderFrame(const TrajectoryParams& traj, int frame, cv::Mat* radiance, cv::Mat* depth) const {
  renderBlurred(traj, frame, params_.exposure_time_s, params_.motion_blur_samples, radiance, depth);
}

void Renderer::renderFrame(const TrajectoryParams& traj, int frame, double exposure_s, cv::Mat* radiance,
                           cv::Mat* depth) const {
  const double ratio = params_.exposure_time_s > 0.0 ? exposure_s / params_.exposure_time_s : 1.0;
  const long n = std::lround(params_.motion_blur_samples * ratio);
  renderBlurred(traj, frame, exposure_s, static_cast<int>(std::min(16L, std::max(1L, n))), radiance, depth);
}

void Renderer::renderBlurred(const TrajectoryParams& traj, int frame, double exposure_s, int n, cv::Mat* radiance,
                             cv::Mat* depth) const {
  const double t = frameTime(frame);
  if (n <= 1 || exposure_s <= 0.0 || depth) {
    render(cameraPose(traj, t), radiance, depth);  // depth: of the mid-exposure pose
    if (n <= 1 || exposure_s <= 0.0) return;
  }
  // Motion blur: average of n renders spread uniformly over [t - exposure/2, t + exposure/2].
  cv::Mat acc = cv::Mat::zeros(h_, w_, CV_32FC1), sub;
  for (int i = 0; i < n; ++i) {
    const double ts = t + exposure_s * ((i + 0.5) / n - 0.5);
    render(cameraPose(traj, ts), &sub, nullptr);
    acc += sub;
  }
  *radiance = acc / static_cast<double>(n);
}

void Renderer::setPoseInRig(const Eigen::Isometry3d& T_C0_C) {
  if (!T_C0_C.matrix().allFinite()) throw std::invalid_argument("Renderer: the camera's pose in the rig is not finite");
  T_C0_C_ = T_C0_C;
  in_rig_ = T_C0_C.matrix() != Eigen::Matrix4d::Identity();
}

Eigen::Isometry3d Renderer::cameraPose(const TrajectoryParams& traj, double t) const {
  const Eigen::Isometry3d T_W_C0 = trajectoryPose(traj, t);
  return in_rig_ ? T_W_C0 * T_C0_C_ : T_W_C0;
}

bool Renderer::castPixel(const Eigen::Isometry3d& T_W_C, const Eigen::Vector2d& uv, Eigen::Vector3d* p_W,
                         double* depth) const {
  Eigen::Vector3d b;
  if (!camera_->unproject(uv, &b) || !b.allFinite() || b.norm() < 0.5) return false;
  b.normalize();
  const Eigen::Vector3d d = T_W_C.linear() * b;
  SceneHit hit;
  if (!scene_->castRay(T_W_C.translation().cast<float>(), d.cast<float>(), &hit)) return false;
  // Recompute the point in double from the ray parameter for a precise reprojection.
  const double t = hit.t;
  *p_W = T_W_C.translation() + t * d;
  if (depth) *depth = t * b.z();
  return true;
}

}  // namespace iraf_vo
