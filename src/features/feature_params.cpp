#include "iraf_vo/features/feature_params.h"

namespace iraf_vo {

const ParamTable<FeatureParams>& featureParamTable() {
  using P = FeatureParams;
  // The ranges also bound what sizes an allocation (n_features: 4 candidates each are reserved) or a loop.
  static const ParamTable<P> table(
      "features",
      {
          intParam("n_features", &P::n_features, 50, 10000,
                   "Keypoints per image over all levels (ORB-SLAM: 1000 for 752x480)"),
          doubleParam("scale_factor", &P::scale_factor, 1.05, 2.0, "Pyramid scale between levels (ORB-SLAM: 1.2)"),
          intParam("n_levels", &P::n_levels, 1, 16, "Pyramid levels (ORB-SLAM: 8)"),
          intParam("cell_size", &P::cell_size, 8, 512,
                   "FAST cell side [px of the level] = the eq. 16-19 subregion (ORB-SLAM: 35)"),
          boolParam("adaptive_threshold", &P::adaptive_threshold,
                    "On: eqs. 13-20 per cell. Off: ORB-SLAM fixed ini_th_fast / min_th_fast"),
          intParam("ini_th_fast", &P::ini_th_fast, 1, 254,
                   "Fixed FAST threshold when adaptive_threshold is off (ORB-SLAM: 20)"),
          intParam("min_th_fast", &P::min_th_fast, 1, 254,
                   "Retry threshold for empty cells when adaptive_threshold is off (ORB-SLAM: 7)"),
          doubleParam("alpha", &P::alpha, 0.0, 10.0,
                      "eq. 15: weight of the entropy F_h [bits]. 1.35 with beta 0.15: F_t^g ~20 on EuRoC, ~9.3 on "
                      "EuRoC x0.2, 6..23 on DICM/LIME"),
          doubleParam("beta", &P::beta, 0.0, 5.0,
                      "eq. 15: weight of the mean Sobel magnitude F_g (EuRoC F_g ~63, x0.2 ~12.5)"),
          doubleParam("delta", &P::delta, 0.0, 10.0,
                      "eq. 19: F_t^l = delta |I_m - t_o|. 1.0: median cell threshold ~20 on EuRoC"),
          doubleParam("ft_min", &P::ft_min, 1.0, 254.0,
                      "eq. 20: lower clip F_t,min (= ORB-SLAM minThFAST); retry threshold for empty cells"),
          boolParam("fast_path", &P::fast_path,
                    "On: each row of cells in one FAST-9 pass with per-cell thresholds (detectFast9, ~1.02x faster "
                    "front-end). Off (default): reference path, the corners of cv::FAST per strip + runs"),
          intParam("center_window", &P::center_window, 1, 31,
                   "eq. 19: I_m = mean of this odd window at the cell centre (1 = paper's single pixel)", /*odd=*/true),
          boolParam("cell_mean_contrast", &P::cell_mean_contrast,
                    "eq. 19 over the whole cell: F_t^l = delta mean|I - t_o| (stable under motion and exposure "
                    "steps); off (default): |I_m - t_o| of the centre_window patch"),
          boolParam("culling", &P::culling, "On: remove keypoints with stability S < s_min (eqs. 21-23)"),
          intParam("min_node_size", &P::min_node_size, 1, 512,
                   "eq. 21: quad-tree leaves are not split below this side [level-0 px]"),
          intParam("contrast_patch_size", &P::contrast_patch_size, 3, 63,
                   "eq. 22: H_c = std-dev of this odd patch around the keypoint on its level", /*odd=*/true),
          doubleParam("rho", &P::rho, 0.0, 10.0, "eq. 22: sigmoid sensitivity rho"),
          doubleParam("h_th", &P::h_th, 0.0, 128.0, "eq. 22: contrast threshold H_th [grey-level std-dev]"),
          doubleParam("k", &P::k, 0.0, 100.0, "eq. 23: density sigmoid sharpness k"),
          doubleParam("d_opt", &P::d_opt, 0.0, 10.0, "eq. 23: D_opt in units of the frame's mean keypoint density"),
          doubleParam("w1", &P::w1, 0.0, 1.0, "eq. 23: density weight w1"),
          doubleParam("w2", &P::w2, 0.0, 1.0, "eq. 23: lighting weight w2"),
          doubleParam("s_min", &P::s_min, 0.0, 1.0, "Keypoints with S < s_min are culled"),
          intParam("min_features", &P::min_features, 0, 10000,
                   "Never cull below this many keypoints (the highest-S ones are kept)"),
          boolParam("eq23_literal", &P::eq23_literal,
                    "eq. 23 as printed, w2 (1 - C_light) (rewards low contrast); off = stated intent w2 C_light"),
      });
  return table;
}

std::string validate(const FeatureParams& p) { return featureParamTable().validate(p); }

}  // namespace iraf_vo
