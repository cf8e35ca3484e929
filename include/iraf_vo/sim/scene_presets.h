// Scenes that fit the simulator's motions (ROS-free):
//   street  (drive)  a street along the gently curving drive path: asphalt ground plane, building blocks
//                    on both sides (facades with windows, 6-11 m from the centreline, 7-25 m high, side-street
//                    gaps, a second row 30-45 m out), parked cars, trees, street lamps; emissive sky ceiling
//                    at 40 m; sun light. Seen from the camera: facades and objects at ~3-50 m.
//   highway (highway) an open road along the drive path: a worn, low-contrast road surface (ground plane),
//                    delineator posts and a few signs 8-10 m out, single trees 15-30 m, tree lines 40-90 m,
//                    buildings 90-220 m out, a skyline 320 m beyond the path, sky at 60 m. Seen from the camera:
//                    little within 15 m besides the road, most texture tens to hundreds of metres away.
//   slider  (slider) a table with objects 0.3-1 m in front of the slider, boxes at 2-3 m, a far wall with
//                    photo posters 4 m away (room 6 x 7 x 2.6 m).
//   room    (room, handheld_fast) Scene::makeDefaultRoom.
// Texture statistics per surface type (facades, asphalt, foliage, sky) in street_textures.cpp.
#pragma once

#include <opencv2/core.hpp>

#include "iraf_vo/sim/scene.h"
#include "iraf_vo/sim/trajectory.h"

namespace iraf_vo {

/// The street around the drive path for arc lengths [-40, path_length_m + 80] m (deterministic for params.seed).
/// params.room_* / light_* / ceiling_shade are set by the function; texels_per_m is used as given.
Scene makeStreetScene(const SceneParams& params, const TrajectoryParams& traj, double path_length_m);

/// The open road around the highway path for arc lengths [-60, path_length_m + 250] m (deterministic for
/// params.seed); the same conventions as makeStreetScene.
Scene makeHighwayScene(const SceneParams& params, const TrajectoryParams& traj, double path_length_m);

/// The slider's table scene. Throws std::invalid_argument when the slider travel does not fit the table (> 3 m).
Scene makeSliderScene(const SceneParams& params, const TrajectoryParams& traj);

/// The scene of traj.motion for a sequence of duration_s seconds.
Scene makeMotionScene(const SceneParams& params, const TrajectoryParams& traj, double duration_s);

/// Surface albedo textures (CV_8UC1, power-of-two sides, wrap around; deterministic for a seed).
/// Facade: plaster with floors 1/5 of the height apart (16 m at 128 texels/m: 3.2 m floors) and a window grid
/// (frames, sills, mullions, dark glass with reflections, some lit / curtained), cornices, grime streaks.
cv::Mat makeFacadeTexture(int width, int height, double texels_per_m, uint64_t seed);
/// Asphalt: fine aggregate grain, repair patches, cracks, manholes, oil stains, sparse lane-marking dashes.
cv::Mat makeAsphaltTexture(int width, int height, double texels_per_m, uint64_t seed);
/// Tree crowns: dense leaf clusters (3-15 cm) on a dark base.
cv::Mat makeFoliageTexture(int width, int height, double texels_per_m, uint64_t seed);
/// Sky: bright, smooth clouds (2-10 m cells), little texture.
cv::Mat makeSkyTexture(int width, int height, double texels_per_m, uint64_t seed);

}  // namespace iraf_vo
