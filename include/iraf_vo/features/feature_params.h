// Parameters of the feature stage (paper II-B adaptive thresholding, II-C feature culling): the struct (its
// initializers are the defaults) and its parameter table (common/param_table.h): names = field names =
// cfg/Features.cfg parameters = YAML `features:` keys = `--set features.key=value`. ROS-free.
#pragma once

#include <string>

#include "iraf_vo/common/param_table.h"

namespace iraf_vo {

struct FeatureParams {
  // ---- ORB pyramid / distribution (ORB-SLAM defaults for 752x480) ----
  int n_features = 1000;      // total over all levels, split as a geometric series (ORB-SLAM)
  double scale_factor = 1.2;  // pyramid scale between levels
  int n_levels = 8;
  int cell_size = 35;         // FAST cell side [px of the level image] (ORB-SLAM W = 35)

  // ---- FAST threshold ----
  // adaptive_threshold off = ORB-SLAM: every cell ini_th_fast, empty cells retried with min_th_fast.
  bool adaptive_threshold = true;
  int ini_th_fast = 20;
  int min_th_fast = 7;
  // eq. (15): F_t^g = alpha * F_h + beta * F_g, F_h in bits (log2), F_g = mean 3x3-Sobel magnitude.
  // Chosen on EuRoC MH_01 (F_h ~ 7.6 bits, F_g ~ 63), its x0.2 darkened copy (F_h ~ 5.5, F_g ~ 12.5) and
  // the DICM/LIME low-light stills: F_t^g ~ 20 (= ORB-SLAM's iniThFAST) on well-exposed EuRoC frames,
  // ~ 9.3 on the darkened ones, 6..23 on the stills. A higher ceiling (alpha 2, beta 0.3 -> ~34) lost
  // 5-25 % of the matched inliers between nearby EuRoC frames (docs/decisions.md).
  double alpha = 1.35;
  double beta = 0.15;
  // eq. (19): F_t^l = delta * |I_m - t_o|. 1.0: on EuRoC ~55 % of the level-0 cells reach the F_t^g
  // ceiling (median cell threshold = F_t^g ~ 20), ~21 % sit at ft_min.
  double delta = 1.0;
  // eq. (20): lower clip F_t,min^l (= ORB-SLAM's minThFAST); also the retry threshold for cells where F_t
  // found nothing.
  double ft_min = 7.0;
  // I_m of eq. (19): mean of a center_window x center_window patch at the cell centre
  // (1 = the paper's single centre pixel; larger is robust to noise).
  int center_window = 5;
  // I_m of eq. (19) over the whole cell: F_t^l = delta * mean over the cell's pixels of |I - t_o|, the expectation of
  // |I_m - t_o| over where the centre falls. The centre patch makes a cell's threshold jump as the content under it
  // moves (median change 14 % for a 2-px shift vs 2 %). Not the default: sim ae_hunting pinhole ATE 9.3 / 7.6 mm vs
  // 11.1 / 8.4 (means over n_features 990-1010), but clean EuRoC 0-305 4.74 mm vs 4.38 (docs/decisions.md).
  bool cell_mean_contrast = false;
  // FAST with the per-cell thresholds. true: each row of cells in one FAST-9 pass whose threshold is per
  // column (= every cell's own F_t of eq. 20, detectFast9), ~1.02x faster front-end. false (default): the
  // reference path, the corners of cv::FAST per row of cells at a strip threshold + per run of lower-threshold
  // cells, filtered by their cell's threshold (computed bit for bit by one detectFast9 pass per row). Same corners except non-max suppression at run borders and the order
  // of equal-score candidates (97-98 % identical keypoints); identical with adaptive_threshold off. Not the
  // default yet: on the sim dark preset its ATE is ~2x the reference path's over 8 n_features perturbations
  // (docs/decisions.md), unexplained so far.
  bool fast_path = false;

  // ---- feature culling (eqs. 21-23) ----
  bool culling = true;
  int min_node_size = 16;          // eq. (21): quad-tree leaves are not split below this side [level-0 px]
  int contrast_patch_size = 15;    // H_c = std-dev of this patch around the keypoint on its level image
  double rho = 0.5;                // eq. (22): sigmoid sensitivity
  double h_th = 6.0;               // eq. (22): contrast threshold H_th [grey levels of std-dev]
  double k = 4.0;                  // eq. (23): density sigmoid sharpness
  double d_opt = 0.5;              // eq. (23): D_opt, in units of the frame's mean keypoint density
  double w1 = 0.5;                 // eq. (23): density weight
  double w2 = 0.5;                 // eq. (23): lighting weight (w1 + w2 = 1 in the paper)
  // Keypoints with S < s_min are culled. 0.4 culls 0.2-1.2 % of the keypoints; 0.75 culls 5-12 %, whose tracking
  // inlier rate is 0.39-0.49x the kept ones' (iraf_vo_culling_table, docs/decisions.md), but made the Sim(3)
  // ATE worse on the sim dark / mixed presets, so it is not the default.
  double s_min = 0.4;
  int min_features = 300;          // never cull below this many keypoints (the highest-S ones are kept)
  // eq. (23) as printed uses w2 * (1 - C_light), which rewards LOW contrast although the text says low
  // C_light marks unstable regions. false (default) = follow the stated intent: w2 * C_light.
  bool eq23_literal = false;
};


/// Every FeatureParams field with its accepted range and doc (a new field needs a row here and in the cfg).
const ParamTable<FeatureParams>& featureParamTable();

/// Returns a message naming each field out of its table range, or "" when the params are usable.
std::string validate(const FeatureParams& p);

}  // namespace iraf_vo
