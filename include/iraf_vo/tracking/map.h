// The local map: keyframes, map points, their observations and covisibility, under one mutex owned by
// Map. Shared by the tracking thread and the local-mapping thread; every method locks. ROS-free.
//
// Bounded memory: dropOldKeyframes keeps at most max_map_keyframes keyframes; the oldest one is dropped with
// its observations, and points without observations are deleted.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/tracking/frame.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <utility>
#include <vector>

namespace iraf_vo {

struct MapPoint {
  long id = 0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Descriptor desc{};        // ORB-SLAM's distinctive descriptor (updateDescriptors)
  int octave = 0;
  float angle = -1.f;
  std::map<long, int> obs;  // keyframe id -> keypoint index
  long first_kf = 0;        // keyframe that created the point
  int visible = 1, found = 1;
  bool candidate = false;   // triangulated below the parallax gate: tracked and bundle-adjusted, not yet used for
                            // a pose (Map::promoteCandidates)
  int stereo_obs = 0;       // right-image observations: a point from a stereo keyframe counts twice (ORB-SLAM)
  /// Keyframe observations plus right-image ones: what the culling and the keyframe rule count.
  size_t observations() const { return obs.size() + static_cast<size_t>(stereo_obs); }
};

struct Keyframe {
  long id = 0;
  long frame_index = 0;
  double stamp = 0.0;
  double scale_factor = 1.2;
  Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
  // immutable after creation:
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  std::vector<Eigen::Vector3d> bearings;
  std::vector<char> valid;
  std::vector<Eigen::Vector3f> right_obs;  // Frame::right_obs (stereo keyframe), empty otherwise
  // guarded by the map mutex:
  std::vector<long> point_id;
  std::atomic<bool> triangulated{false};  // new points created already (LocalMapper::createNewMapPoints)

  /// A keyframe with the frame's keypoints and no observations yet (id assigned by the map).
  static std::shared_ptr<Keyframe> fromFrame(const Frame& f, const Eigen::Isometry3d& T_c_w);
  double sigma(int octave) const { return octaveSigma(scale_factor, octave); }
};

using KeyframePtr = std::shared_ptr<Keyframe>;
using MapPointPtr = std::shared_ptr<MapPoint>;

/// What the tracking thread matches against: a copy of a map point's position and appearance.
struct LocalPoint {
  long id;
  Eigen::Vector3d p_w;
  Descriptor desc;
  int octave;  // of the keypoint that created the point
  float angle;
  // Scale prediction: the point shows at ref_octave from ref_center (the oldest keyframe in the map observing it),
  // with the image scale ref_scale there (imageScale; 0 = not computed: the distance ratio stands in for it).
  Eigen::Vector3d ref_center = Eigen::Vector3d::Zero();
  int ref_octave = 0;
  double ref_scale = 0.0;
  bool has_ref = false;
  bool candidate = false;  // MapPoint::candidate: matched and kept, but no pose term
};

/// Pixels per metre of a small patch facing the camera at the point where the projection Jacobian J (2x3) was
/// taken: det(J J^T)^(1/4), the geometric mean of J's two singular values (J maps the ray direction to 0). For a
/// pinhole at the image centre f / z; a fisheye shrinks the periphery, a pinhole stretches it.
double imageScale(const Eigen::Matrix<double, 2, 3>& J);

/// ORB-SLAM's scale prediction (MapPoint::PredictScale with Frame::isInFrustum's viewing-angle test), from the
/// point's reference view: seen from `center` with image scale `scale` (imageScale) the point shows at octave
/// ref_octave + log(scale / ref_scale) / log(scale_factor), rounded and >= 0 (ORB-SLAM uses d_ref / d for the
/// ratio, which holds for a pinhole near the image centre only; it stands in when either scale is 0). False when
/// the view direction turned by more than 60 deg from the reference one or the point is more than one octave
/// farther than octave 0 resolves (the descriptor would not match). Without a reference
/// (has_ref false) the point's own octave is returned.
bool predictOctave(const LocalPoint& lp, const Eigen::Vector3d& center, double scale, double scale_factor, int* octave);

/// A point triangulated between keypoint kp_a of keyframe kf_a (gives descriptor, octave, angle) and kp_b of kf_b.
struct NewMapPoint {
  Eigen::Vector3d p_w;
  long kf_a;
  int kp_a;
  long kf_b;
  int kp_b;
  bool candidate = false;  // its parallax is below the gate (MapPoint::candidate)
};

/// A point of one stereo keyframe: its left keypoint and the position from the left-right triangulation.
struct StereoMapPoint {
  int kp = -1;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
};

/// A keyframe to triangulate against, with a copy of its pose and observations taken under the lock.
struct TriangulationNeighbor {
  KeyframePtr keyframe;
  Eigen::Isometry3d T_c_w;
  std::vector<long> point_id;
};

/// Everything createNewMapPoints needs, copied under the map lock.
struct TriangulationInput {
  KeyframePtr keyframe;
  Eigen::Isometry3d T_c_w;
  std::vector<long> point_id;
  std::vector<TriangulationNeighbor> neighbors;  // most covisible first, then the most recent keyframes
  double median_depth = 1.0;
};

/// Keyframe poses as published.
struct KeyframePose {
  long id = 0;
  double stamp = 0.0;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
};

struct LocalBAProblem;
struct BASummary;
struct FusionTarget;
struct FusionLink;

class Map {
 public:
  // ---- map creation ----
  /// Adds a new map's first two keyframes and the points triangulated between them (NewMapPoint with
  /// kf_a = kf1, kf_b = kf0; the ids in the points are ignored). Fewer than min_points points -> rolled back,
  /// returns false. *created = points created (before a roll-back).
  bool createInitialMap(const KeyframePtr& kf0, const KeyframePtr& kf1, const std::vector<NewMapPoint>& points,
                        int min_points, int* created);
  /// Adds a stereo map's first keyframe and the points of its left-right matches (metric from one frame). Fewer
  /// than min_points points -> nothing added, returns false. *created = points created (before a roll-back).
  bool createStereoMap(const KeyframePtr& kf, const std::vector<StereoMapPoint>& points, int min_points,
                       int* created);
  /// Adds the stereo points of keyframe kf_id at its keypoints that have no point yet (recent points, culled
  /// as triangulated ones). Returns the number added.
  int addStereoPoints(long kf_id, const std::vector<StereoMapPoint>& points);
  /// Adds a keyframe made from a tracked frame: its matched points (f.point_id) become observations.
  long addKeyframe(const Frame& f);
  void clear();

  // ---- tracking thread ----
  /// The map-update lock (ORB-SLAM's mMutexMapUpdate): the tracking thread holds it over one frame (pose from
  /// the map's points, keyframe creation and mapping, the last frame's pose relative to its keyframe) and
  /// writes BA results back either under it (threaded mapping, at the next keyframe) or takes it for that
  /// (synchronous mapping, after the tracking step), so BA results never land in the middle of a tracking step.
  /// The mapping thread never takes it.
  std::unique_lock<std::mutex> lockUpdates() { return std::unique_lock<std::mutex>(update_mutex_); }
  /// With a camera, each point's scale-prediction reference too (LocalPoint::ref_*; predictOctave), else none.
  std::vector<LocalPoint> localPoints(const CameraModel* camera = nullptr) const;
  bool keyframePose(long id, Eigen::Isometry3d* T_c_w) const;
  /// The ids of the map points each keyframe observes, newest keyframe first (relocalization candidates).
  std::vector<std::vector<long>> pointsByKeyframe() const;
  /// Points seen in the frame's view (visible) and matched (found): ORB-SLAM's found ratio.
  void countVisibility(const std::vector<LocalPoint>& local, const std::vector<char>& visible,
                       const std::vector<int>& keypoint_of_point);
  /// Points of keyframe kf_id observed by >= min_observations keyframes; with `nearer`, also how many of them are
  /// nearer than max_depth to that keyframe (one pass).
  int trackedPoints(long kf_id, size_t min_observations, double max_depth = 0.0, int* nearer = nullptr) const;
  /// The keyframe observing the most of these points (ORB-SLAM's reference keyframe); `fallback` when none does.
  long mostCovisibleKeyframe(const std::vector<long>& ids, long fallback) const;
  /// Of the points ids (-1: none) those nearer than max_depth to a camera at T_c_w.
  int pointsNearerThan(const std::vector<long>& ids, const Eigen::Isometry3d& T_c_w, double max_depth) const;

  // ---- local mapping ----
  /// Erases recent points found in fewer than min_found_ratio of the frames that saw them, or observed by
  /// <= 2 keyframes two keyframes after their creation.
  void cullRecentPoints(long current_kf, double min_found_ratio);
  /// ORB-SLAM's distinctive descriptor for the points seen by a keyframe.
  void updateDescriptors(long kf_id);
  /// Claims a keyframe for triangulation (false if done already or gone) and copies its inputs.
  bool claimForTriangulation(long kf_id, int num_neighbors, TriangulationInput* in);
  /// Adds triangulated points (kf_a = the new keyframe) unless a keypoint got a point meanwhile.
  void addTriangulatedPoints(const std::vector<NewMapPoint>& points);
  void dropOldKeyframes(int max_keyframes);
  /// Candidate points among point_ids whose observing keyframes' rays now span at least the parallax whose cosine
  /// is cos_gate (after a BA moved them) become ordinary points; returns how many.
  int promoteCandidates(const std::vector<long>& point_ids, double cos_gate);

  // ---- queries (any thread) ----
  std::vector<Eigen::Vector3d> pointPositions() const;
  std::vector<KeyframePose> keyframePoses() const;
  size_t numKeyframes() const;
  size_t numPoints() const;

 private:
  // The local BA's and the fusion's side of the map (local_ba.h, map_fusion.h) work on the map's data under its lock.
  friend LocalBAProblem buildLocalBAProblem(const Map& map, int window_size, double min_fixed_span, bool stereo);
  friend void applyLocalBA(const LocalBAProblem& problem, const BASummary& summary, Map* map);
  friend std::vector<FusionTarget> fusionTargets(const Map& map, long kf_id, int num_neighbors,
                                                 const CameraModel* camera);
  friend std::pair<int, int> applyFusion(const std::vector<FusionLink>& links, Map* map);

  long createPointLocked(const Eigen::Vector3d& p_w, Keyframe& a, int kp_a, Keyframe& b, int kp_b);
  long createStereoPointLocked(const Eigen::Vector3d& p_w, Keyframe& kf, int kp);
  MapPoint& newPointLocked(const Eigen::Vector3d& p_w, Keyframe& kf, int kp);
  void erasePointLocked(long id);
  /// Moves gone's observations to keep (where keep has none in that keyframe) and erases gone (applyFusion).
  void mergePointsLocked(MapPoint* keep, MapPoint* gone);
  LocalPoint localPointLocked(const MapPoint& mp, const CameraModel* camera) const;
  /// (shared points, keyframe id) of every keyframe but `exclude` observing points of `ids` (-1: none), the most
  /// shared first, then the newest; fill_recent: then (0, id) of the other keyframes, newest first.
  std::vector<std::pair<int, long>> covisibilityLocked(const std::vector<long>& ids, long exclude,
                                                       bool fill_recent = false) const;

  std::mutex update_mutex_;  // lockUpdates(); taken before mutex_
  mutable std::mutex mutex_;
  std::map<long, KeyframePtr> keyframes_;
  std::unordered_map<long, MapPointPtr> points_;
  std::vector<long> recent_points_;
  long next_keyframe_id_ = 0, next_point_id_ = 0;
};

}  // namespace iraf_vo
