#include "iraf_vo/tracking/multiview.h"
#include "iraf_vo/tracking/relocalizer.h"

#include <algorithm>
#include <cstring>
#include <unordered_map>

namespace iraf_vo {

std::vector<RelocalizationCandidate> Relocalizer::candidates(const Frame& cur, const Map& map,
                                                             size_t max_candidates) const {
  std::vector<RelocalizationCandidate> out;
  if (cur.size() == 0 || cur.descriptors.empty()) return out;
  const std::vector<LocalPoint> local = map.localPoints();
  std::unordered_map<long, size_t> index_of;
  for (size_t i = 0; i < local.size(); ++i) index_of[local[i].id] = i;
  const std::vector<std::vector<long>> by_keyframe = map.pointsByKeyframe();
  for (size_t rank = 0; rank < by_keyframe.size(); ++rank) {
    std::vector<size_t> points;
    for (long id : by_keyframe[rank]) {
      auto it = index_of.find(id);
      if (it != index_of.end()) points.push_back(it->second);
    }
    if (static_cast<int>(points.size()) < kMinMatches) continue;
    cv::Mat D(static_cast<int>(points.size()), 32, CV_8U);
    std::vector<float> angles(points.size());
    for (size_t k = 0; k < points.size(); ++k) {
      std::memcpy(D.ptr<uint8_t>(static_cast<int>(k)), local[points[k]].desc.data(), 32);
      angles[k] = local[points[k]].angle;
    }
    const auto m = matcher_.matchBruteForce(cur.descriptors, cur.keypoints, cur.valid, D, angles,
                                            p_.match_threshold_high, p_.match_ratio);
    if (static_cast<int>(m.size()) < kMinMatches) continue;
    std::vector<Eigen::Vector3d> P, B;
    for (const auto& x : m) {
      P.push_back(local[points[x.second]].p_w);
      B.push_back(cur.bearings[x.first]);
    }
    RelocalizationCandidate c;
    c.keyframe_rank = static_cast<int>(rank);
    c.pnp_inliers = solvePnPBearings(P, B, cam_.focal(), p_.pnp_threshold_px, p_.pnp_iterations, &c.T_c_w);
    if (c.pnp_inliers >= kMinPnPInliers) out.push_back(c);
    if (c.pnp_inliers >= kEnoughPnPInliers) break;  // the newest keyframes are the likeliest: no need to go on
  }
  std::stable_sort(out.begin(), out.end(), [](const RelocalizationCandidate& a, const RelocalizationCandidate& b) {
    return a.pnp_inliers > b.pnp_inliers;
  });
  if (out.size() > max_candidates) out.resize(max_candidates);
  return out;
}

}  // namespace iraf_vo
