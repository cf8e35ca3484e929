#include "iraf_vo/sim/scene_presets.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace iraf_vo {

namespace {

int nextPow2(double v) {
  int p = 16;
  while (p < v) p <<= 1;
  return p;
}

SceneBox makeBox(double x0, double y0, double z0, double x1, double y1, double z1, int texture) {
  return SceneBox{Eigen::Vector3f(x0, y0, z0), Eigen::Vector3f(x1, y1, z1), texture};
}

/// The street centreline sampled every metre, with the left normals.
struct Polyline {
  std::vector<Eigen::Vector2d> p, left;
  std::vector<double> s;
};

Polyline samplePath(const TrajectoryParams& traj, double s0, double s1) {
  Polyline pl;
  for (double s = s0; s <= s1; s += 1.0) {
    double h = 0;
    pl.p.push_back(drivePath(traj, s, &h));
    pl.left.emplace_back(-std::sin(h), std::cos(h));
    pl.s.push_back(s);
  }
  return pl;
}

/// Distance from the centreline (all samples) to the footprint of the axis-aligned box.
double clearance(const Polyline& pl, const SceneBox& b) {
  double best = 1e30;
  for (const Eigen::Vector2d& q : pl.p) {
    const double dx = std::max({b.lo.x() - q.x(), 0.0, q.x() - b.hi.x()});
    const double dy = std::max({b.lo.y() - q.y(), 0.0, q.y() - b.hi.y()});
    best = std::min(best, std::hypot(dx, dy));
  }
  return best;
}

/// Adds an object of footprint sx x sy (m), z in [z0, z1], whose centre is `offset` m to the `side` (+1 left,
/// -1 right) of the centreline at arc length s; pushed outwards until it is >= min_clear from the centreline.
/// Returns the outward shift applied (m) or -1 when the object could not be placed.
double placeBeside(const Polyline& pl, double s, int side, double offset, double sx, double sy, double z0, double z1,
                   int texture, double min_clear, std::vector<SceneBox>* boxes,
                   const std::vector<std::pair<double, double>>& stack = {}) {
  const int i = std::max(0, std::min(static_cast<int>(pl.s.size()) - 1, static_cast<int>(std::lround(s - pl.s[0]))));
  const Eigen::Vector2d n = side * pl.left[i];
  for (double push = 0.0; push < 20.0; push += 0.25) {
    const Eigen::Vector2d c = pl.p[i] + (offset + push) * n;
    SceneBox b = makeBox(c.x() - sx / 2, c.y() - sy / 2, z0, c.x() + sx / 2, c.y() + sy / 2, z1, texture);
    if (clearance(pl, b) < min_clear) continue;
    boxes->push_back(b);
    // Stacked parts (car cabin, lamp head...): (size scale, z1) pairs sharing the centre.
    for (const auto& st : stack)
      boxes->push_back(makeBox(c.x() - st.first * sx / 2, c.y() - st.first * sy / 2, z1, c.x() + st.first * sx / 2,
                               c.y() + st.first * sy / 2, st.second, texture));
    return push;
  }
  return -1.0;
}

/// Outdoor scene parameters around the sampled path: the room's walls `wall_margin_m` beyond the path's extent (the
/// distant skyline), an emissive sky at sky_m, the sun far away (elevation ~40 deg) from the left-front.
SceneParams outdoorParams(const SceneParams& params, const Polyline& pl, double wall_margin_m, double sky_m,
                          double sky_shade) {
  double max_x = 0, max_y = 0;
  for (const auto& q : pl.p) max_x = std::max(max_x, std::abs(q.x())), max_y = std::max(max_y, std::abs(q.y()));
  SceneParams sp = params;
  sp.room_x = 2 * (max_x + wall_margin_m);
  sp.room_y = 2 * (max_y + wall_margin_m);
  sp.room_z = sky_m;
  const Eigen::Vector3d sun = Eigen::Vector3d(0.35, 0.6, 0.72).normalized() * 1e5;
  sp.light_x = sun.x(), sp.light_y = sun.y(), sp.light_z = sun.z();
  sp.light_range_m = 1e7;
  sp.ambient = 0.42;
  sp.ceiling_shade = sky_shade;
  return sp;
}

}  // namespace

Scene makeStreetScene(const SceneParams& params, const TrajectoryParams& traj, double path_length_m) {
  if (!(path_length_m >= 0.0)) throw std::invalid_argument("makeStreetScene: path_length_m must be >= 0");
  const double tpm = params.texels_per_m;
  const double s0 = -40.0, s1 = path_length_m + 80.0;
  const Polyline pl = samplePath(traj, s0, s1);
  // Distant city walls 90 m beyond the path; sun from the left-front: left facades lit, right ones in shade.
  const SceneParams sp = outdoorParams(params, pl, 90.0, 40.0, 1.12);

  cv::RNG rng(params.seed * 6364136223846793005ull + 1442695040888963407ull);
  const uint64_t ts = params.seed * 32;
  const int fw = nextPow2(32 * tpm), fh = nextPow2(16 * tpm);
  // Textures: 0-3 facades (also the distant walls), 4 asphalt, 5 sky, 6 foliage, 7-8 cars, 9 poles and trunks,
  // 10-11 more facades.
  std::vector<SceneTexture> tex;
  const float ftpm = static_cast<float>(tpm);
  for (int i = 0; i < 4; ++i) tex.emplace_back(makeFacadeTexture(fw, fh, tpm, ts + i), ftpm);
  tex.emplace_back(makeAsphaltTexture(nextPow2(32 * tpm), nextPow2(32 * tpm), tpm, ts + 4), ftpm);
  tex.emplace_back(makeSkyTexture(nextPow2(16 * tpm), nextPow2(16 * tpm), tpm, ts + 5), ftpm);
  tex.emplace_back(makeFoliageTexture(nextPow2(8 * tpm), nextPow2(8 * tpm), tpm, ts + 6), ftpm);
  for (int i = 0; i < 3; ++i)
    tex.emplace_back(makeProceduralTexture(nextPow2(4 * tpm), nextPow2(4 * tpm), tpm, ts + 7 + i), ftpm);
  for (int i = 0; i < 2; ++i) tex.emplace_back(makeFacadeTexture(fw, fh, tpm, ts + 10 + i), ftpm);
  const int facade[] = {0, 1, 2, 3, 10, 11};

  std::vector<SceneBox> boxes;
  for (int side : {1, -1}) {
    // Front row of building blocks, with side-street gaps; a taller second row 30-45 m out.
    for (double s = s0; s < s1;) {
      const double len = rng.uniform(8.0, 22.0);
      const double depth = rng.uniform(10.0, 18.0), height = rng.uniform(7.0, 25.0);
      const double setback = rng.uniform(6.0, 11.0);
      placeBeside(pl, s + len / 2, side, setback + depth / 2, len, depth, 0.0, height, facade[rng.uniform(0, 6)], 5.5,
                  &boxes);
      s += len + (rng.uniform(0.0, 1.0) < 0.15 ? rng.uniform(8.0, 14.0) : rng.uniform(0.0, 1.5));
    }
    for (double s = s0; s < s1;) {
      const double len = rng.uniform(15.0, 30.0), depth = rng.uniform(12.0, 25.0);
      placeBeside(pl, s + len / 2, side, rng.uniform(30.0, 45.0) + depth / 2, len, depth, 0.0, rng.uniform(15.0, 35.0),
                  facade[rng.uniform(0, 6)], 25.0, &boxes);
      s += len + rng.uniform(0.0, 4.0);
    }
    // Parked cars along the kerb (body + cabin), trees, street lamps.
    for (double s = s0; s < s1; s += 6.5)
      if (rng.uniform(0.0, 1.0) < 0.4)
        placeBeside(pl, s, side, 4.3 + rng.uniform(-0.2, 0.2), 4.3, 1.8, 0.18, 1.0, 7 + rng.uniform(0, 2), 3.2, &boxes,
                    {{0.6, 1.45}});
    for (double s = s0 + 3.0; s < s1; s += 9.0)
      if (rng.uniform(0.0, 1.0) < 0.5) {
        const double crown = rng.uniform(2.2, 3.2);
        placeBeside(pl, s, side, 5.8, 0.3, 0.3, 0.0, 2.8, 9, 3.6 + crown / 2, &boxes);
        placeBeside(pl, s, side, 5.8, crown, crown, 2.6, 2.6 + rng.uniform(2.5, 4.0), 6, 3.6, &boxes);
      }
    for (double s = s0 + 10.0; s < s1; s += 25.0)
      placeBeside(pl, s, side, 5.2, 0.16, 0.16, 0.0, 6.0, 9, 4.0, &boxes, {{3.0, 6.25}});
  }
  return Scene(sp, std::move(tex), std::move(boxes));
}

Scene makeHighwayScene(const SceneParams& params, const TrajectoryParams& traj, double path_length_m) {
  if (!(path_length_m >= 0.0)) throw std::invalid_argument("makeHighwayScene: path_length_m must be >= 0");
  const double tpm = params.texels_per_m;
  const double s0 = -60.0, s1 = path_length_m + 250.0;
  const Polyline pl = samplePath(traj, s0, s1);
  // Hills / skyline 320 m beyond the path; a hazy sky at 60 m, mostly below saturation at the drive's exposure.
  const SceneParams sp = outdoorParams(params, pl, 320.0, 60.0, 0.8);

  cv::RNG rng(params.seed * 2862933555777941757ull + 7046029254386353131ull);
  const uint64_t ts = params.seed * 32 + 16;
  const int fw = nextPow2(32 * tpm), fh = nextPow2(16 * tpm);
  // Textures: 0-3 facades (buildings and the distant skyline), 4 road, 5 sky, 6 foliage, 7-8 signs / posts.
  std::vector<SceneTexture> tex;
  const float ftpm = static_cast<float>(tpm);
  for (int i = 0; i < 4; ++i) tex.emplace_back(makeFacadeTexture(fw, fh, tpm, ts + i), ftpm);
  // Worn road surface: the asphalt's contrast cut to 60 % (fainter grain and patches).
  cv::Mat road = makeAsphaltTexture(nextPow2(32 * tpm), nextPow2(32 * tpm), tpm, ts + 4);
  road.convertTo(road, CV_8U, 0.6, 0.4 * cv::mean(road)[0]);
  tex.emplace_back(road, ftpm);
  // Open, hazy sky seen at grazing angles up to the horizon: even (the street's clouds alias into a moire here).
  const cv::Mat sky = makeSkyTexture(nextPow2(16 * tpm), nextPow2(16 * tpm), tpm, ts + 5);
  tex.emplace_back(cv::Mat(sky.size(), CV_8UC1, cv::Scalar(cv::mean(sky)[0])), ftpm);
  tex.emplace_back(makeFoliageTexture(nextPow2(8 * tpm), nextPow2(8 * tpm), tpm, ts + 6), ftpm);
  for (int i = 0; i < 2; ++i)
    tex.emplace_back(makeProceduralTexture(nextPow2(4 * tpm), nextPow2(4 * tpm), tpm, ts + 7 + i), ftpm);

  std::vector<SceneBox> boxes;
  for (int side : {1, -1}) {
    // Near: delineator posts every 50 m and a few signs on the verge (the only structure within 15 m).
    for (double s = s0 + rng.uniform(0.0, 50.0); s < s1; s += 50.0)
      placeBeside(pl, s, side, 8.0, 0.12, 0.12, 0.0, 1.1, 8, 7.0, &boxes);
    for (double s = s0 + rng.uniform(0.0, 120.0); s < s1; s += rng.uniform(100.0, 160.0))
      if (rng.uniform(0.0, 1.0) < 0.5) placeBeside(pl, s, side, 10.0, 1.2, 2.6, 2.2, 4.0, 7, 9.0, &boxes);
    // Single trees 15-30 m out, tree lines (woods) 40-90 m out, buildings 90-220 m out.
    for (double s = s0; s < s1; s += 25.0)
      if (rng.uniform(0.0, 1.0) < 0.35) {
        const double crown = rng.uniform(3.0, 6.0), off = rng.uniform(15.0, 30.0);
        placeBeside(pl, s, side, off, 0.4, 0.4, 0.0, 3.0, 8, off - 1.0, &boxes);
        placeBeside(pl, s, side, off, crown, crown, 2.8, 2.8 + rng.uniform(3.0, 6.0), 6, off - crown, &boxes);
      }
    for (double s = s0; s < s1;) {
      const double len = rng.uniform(20.0, 60.0), depth = rng.uniform(10.0, 25.0);
      if (rng.uniform(0.0, 1.0) < 0.6)
        placeBeside(pl, s + len / 2, side, rng.uniform(40.0, 90.0) + depth / 2, len, depth, 0.0, rng.uniform(8.0, 16.0),
                    6, 35.0, &boxes);
      s += len + rng.uniform(5.0, 40.0);
    }
    for (double s = s0; s < s1;) {
      const double len = rng.uniform(20.0, 50.0), depth = rng.uniform(15.0, 30.0);
      if (rng.uniform(0.0, 1.0) < 0.5)
        placeBeside(pl, s + len / 2, side, rng.uniform(90.0, 220.0) + depth / 2, len, depth, 0.0,
                    rng.uniform(10.0, 30.0), rng.uniform(0, 4), 80.0, &boxes);
      s += len + rng.uniform(20.0, 80.0);
    }
  }
  return Scene(sp, std::move(tex), std::move(boxes));
}

Scene makeSliderScene(const SceneParams& params, const TrajectoryParams& traj) {
  if (!(traj.slider_travel_m > 0.0 && traj.slider_travel_m <= 3.0))
    throw std::invalid_argument("makeSliderScene: slider_travel_m must be in (0, 3] m (got " +
                                std::to_string(traj.slider_travel_m) + ")");
  SceneParams sp = params;
  sp.room_x = 6.0, sp.room_y = 7.0, sp.room_z = 2.6;  // far wall y = 3.5: 4 m from the slider (y = -0.5)
  sp.light_x = 0.3, sp.light_y = 1.0, sp.light_z = 2.5;
  int posters = 0;
  std::vector<cv::Mat> albedo = makeRoomAlbedo(sp, 1.5, &posters);  // posters at eye height
  // Table-top objects (5-16 cm) get the procedural statistics shrunk 6x (features 0.5-10 cm), like printed boxes.
  for (int i = 7; i < 10; ++i)
    albedo[i] = makeProceduralTexture(albedo[i].cols, albedo[i].rows, sp.texels_per_m / 6.0, params.seed * 16 + 40 + i);
  std::vector<SceneTexture> tex;
  for (const auto& a : albedo) tex.emplace_back(a, static_cast<float>(sp.texels_per_m));
  cv::RNG rng(params.seed * 2862933555777941757ull + 3037000493ull);
  const double y_cam = traj.slider_y_m;
  std::vector<SceneBox> boxes = {makeBox(-1.8, y_cam + 0.25, 0.0, 1.8, y_cam + 1.9, 0.72, 6)};  // table
  // Objects on the table 0.3-1.0 m in front of the slider, spread over its travel (+ margin).
  const int n = 9;
  const double span = traj.slider_travel_m / 2 + 0.45;
  for (int i = 0; i < n; ++i) {
    const double x = -span + 2 * span * (i + rng.uniform(0.2, 0.8)) / n;
    const double d = 0.3 + 0.7 * ((i * 5) % n) / (n - 1.0);  // depths interleaved: near next to far
    const double sx = rng.uniform(0.05, 0.16), sy = rng.uniform(0.05, 0.16), hgt = rng.uniform(0.15, 0.45);
    boxes.push_back(makeBox(x - sx / 2, y_cam + d, 0.72, x + sx / 2, y_cam + d + sy, 0.72 + hgt, 7 + i % 3));
  }
  // Larger boxes on the floor behind the table, 2.5-3.3 m away.
  for (int i = 0; i < 3; ++i) {
    const double x = -1.6 + 1.6 * i + rng.uniform(-0.3, 0.3), sz = rng.uniform(0.4, 0.7);
    const double y = y_cam + rng.uniform(2.5, 3.0);
    boxes.push_back(makeBox(x - sz / 2, y, 0.0, x + sz / 2, y + sz, rng.uniform(0.9, 1.6), 6 + i));
  }
  Scene scene(sp, std::move(tex), std::move(boxes));
  scene.setPhotoPosters(posters);
  return scene;
}

Scene makeMotionScene(const SceneParams& params, const TrajectoryParams& traj, double duration_s) {
  switch (traj.motion) {
    case MotionKind::kDrive: {
      const double t_motion = motionClock(traj, duration_s);
      return makeStreetScene(params, traj, traj.drive_speed_mps * t_motion);
    }
    case MotionKind::kHighway: {
      const double t_motion = motionClock(traj, duration_s);
      return makeHighwayScene(params, traj, traj.drive_speed_mps * t_motion);
    }
    case MotionKind::kSlider: return makeSliderScene(params, traj);
    case MotionKind::kRoom:
    case MotionKind::kHandheldFast: break;
  }
  return Scene::makeDefaultRoom(params);
}

}  // namespace iraf_vo
