// StereoMatcher: left-right matches of unrectified pairs through the epipolar constraint on bearings, triangulated
// and checked (synthetic pairs of both camera models with known points; EuRoC MH_01 frame 0).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/pipeline/front_end.h"
#include "iraf_vo/tracking/stereo_matcher.h"
#include "iraf_vo/tracking/stereo_refinement.h"
#include "unit/tracking_test_utils.h"

using namespace iraf_vo;
using namespace iraf_vo::test;

namespace {

/// The tracker's frames of a pair of feature frames (one camera model for both).
void toFrames(const FeatureFrame& fl, const FeatureFrame& fr, const CameraModel& cam, Frame* left, Frame* right) {
  std::string err;
  ASSERT_TRUE(Frame::fromFeatures(fl, cam, 0, left, &err)) << err;
  ASSERT_TRUE(Frame::fromFeatures(fr, cam, 0, right, &err)) << err;
}

/// A rig with a 0.12 m baseline and a 2 deg toe-in (not rectified).
StereoRig syntheticRig(CameraModelPtr cam) {
  StereoRig rig;
  rig.left = cam;
  rig.right = cam;
  rig.T_r_l = makePose(Eigen::Vector3d(0.5, -2.0, 0.3), Eigen::Vector3d(-0.12, 0.004, 0.002));
  return rig;
}

/// Renders the same world into both cameras, matches, and checks the matched points against the truth.
void checkSyntheticPair(CameraModelPtr cam) {
  const StereoRig rig = syntheticRig(cam);
  SyntheticWorld world;
  world.addBox(600, Eigen::Vector3d(-3, -2, 1.0), Eigen::Vector3d(3, 2, 4.5));
  const Eigen::Isometry3d T_w_l = Eigen::Isometry3d::Identity();
  FeatureFrame fl = world.render(*cam, T_w_l, 0.0, 0.3, 4);
  FeatureFrame fr = world.render(*cam, T_w_l * rig.T_r_l.inverse(), 0.0, 0.3, 4);
  TrackerParams p;
  Frame left, right;
  ASSERT_NO_FATAL_FAILURE(toFrames(fl, fr, *cam, &left, &right));
  const StereoMatcher matcher(rig, p);
  const std::vector<StereoMatch> matches = matcher.match(left, right);
  // Which world point each keypoint shows: the nearest projection.
  auto pointOf = [&](const FeatureFrame& f, const Eigen::Isometry3d& T_w_c, int k) {
    int best = -1;
    double bd = 1e9;
    for (size_t i = 0; i < world.points.size(); ++i) {
      Eigen::Vector2d uv;
      const Eigen::Vector3d pc = T_w_c.inverse() * world.points[i];
      if (pc.z() < 0.1 || !cam->project(pc, &uv)) continue;
      const double d = (uv - Eigen::Vector2d(f.keypoints[k].pt.x, f.keypoints[k].pt.y)).norm();
      if (d < bd) bd = d, best = static_cast<int>(i);
    }
    return best;
  };
  int correct = 0;
  std::vector<double> rel_err;
  for (const StereoMatch& m : matches) {
    const int a = pointOf(fl, T_w_l, m.left), b = pointOf(fr, T_w_l * rig.T_r_l.inverse(), m.right);
    if (a != b) continue;
    ++correct;
    rel_err.push_back((m.p_l - world.points[a]).norm() / world.points[a].norm());
  }
  const size_t both = std::min(fl.keypoints.size(), fr.keypoints.size());
  EXPECT_GT(matches.size(), 0.7 * both) << cam->modelName() << ": " << matches.size() << " of " << both;
  EXPECT_GE(correct, static_cast<int>(0.98 * matches.size())) << cam->modelName();
  // 0.3 px noise per image, a 0.12 m baseline, points at 1-4.5 m: the depth error is ~0.42 px / disparity, ~2 %
  // (f 450) or ~5 % (fisheye f 200) at the median depth, ~10-40 % at the far end (4.5 m at the fisheye's periphery:
  // ~2 px of disparity).
  ASSERT_FALSE(rel_err.empty());
  std::sort(rel_err.begin(), rel_err.end());
  EXPECT_LT(rel_err[rel_err.size() / 2], 0.06) << cam->modelName();
  EXPECT_LT(rel_err[rel_err.size() * 95 / 100], 0.25) << cam->modelName();
  for (const StereoMatch& m : matches) EXPECT_LE(m.depth(), matcher.maxDepth());
}

/// 640 x 480 random 8 x 8 px blocks (seed), blurred by sigma px: texture for the patch fits.
cv::Mat blockTexture(int seed, double sigma) {
  cv::RNG rng(seed);
  cv::Mat coarse(60, 80, CV_8UC1), tex;
  rng.fill(coarse, cv::RNG::UNIFORM, 0, 255);
  cv::resize(coarse, tex, cv::Size(640, 480), 0, 0, cv::INTER_NEAREST);
  cv::GaussianBlur(tex, tex, cv::Size(0, 0), sigma);
  return tex;
}

/// A textured plane z = depth (blocks of 0.2 m, blurred) seen by a pinhole camera at x = offset [m]: 8-bit image.
cv::Mat planeImage(const cv::Mat& texture, double texel_m, const PinholeRadtan& cam, double depth, double offset) {
  cv::Mat mx(cam.height(), cam.width(), CV_32FC1), my(cam.height(), cam.width(), CV_32FC1);
  for (int v = 0; v < cam.height(); ++v)
    for (int u = 0; u < cam.width(); ++u) {
      Eigen::Vector3d b;
      cam.unproject(Eigen::Vector2d(u, v), &b);
      const double X = offset + depth * b.x() / b.z(), Y = depth * b.y() / b.z();
      mx.at<float>(v, u) = static_cast<float>(X / texel_m + texture.cols / 2.0);
      my.at<float>(v, u) = static_cast<float>(Y / texel_m + texture.rows / 2.0);
    }
  cv::Mat out;
  cv::remap(texture, out, mx, my, cv::INTER_LINEAR);
  return out;
}

}  // namespace

TEST(StereoRefinement, FindsASubPixelShiftAlongTheRow) {
  cv::Mat coarse(40, 60, CV_8UC1), tex, shifted;
  cv::randu(coarse, 0, 255);
  cv::resize(coarse, tex, cv::Size(600, 400), 0, 0, cv::INTER_NEAREST);
  cv::GaussianBlur(tex, tex, cv::Size(0, 0), 2.0);
  const double shift = 3.37;  // the right image shows the left one moved left by 3.37 px
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, -shift, 0, 1, 0);
  cv::warpAffine(tex, shifted, M, tex.size(), cv::INTER_CUBIC);
  const Eigen::Vector2d ul(300, 200), ur_raw(297, 200);  // an integer right keypoint 0.37 px off
  for (const double step : {1.0, 1.2, 2.0736}) {  // octaves 0, 1, 4
    Eigen::Vector2d ur;
    ASSERT_TRUE(refineAlongEpipolar(tex, shifted, ul, ur_raw, Eigen::Vector2d(1, 0), step, &ur)) << step;
    EXPECT_NEAR(ur.x(), ul.x() - shift, 0.1 * step) << "step " << step;  // a tenth of the level pixel
    EXPECT_DOUBLE_EQ(ur.y(), 200.0);
  }
  Eigen::Vector2d ur;
  EXPECT_FALSE(refineAlongEpipolar(tex, shifted, Eigen::Vector2d(3, 200), ur_raw, Eigen::Vector2d(1, 0), 1.0, &ur))
      << "the left patch leaves the image";
  EXPECT_FALSE(refineAlongEpipolar(tex, shifted, ul, Eigen::Vector2d(285, 200), Eigen::Vector2d(1, 0), 1.0, &ur))
      << "the fit lies beyond the search range";
}

// The parabola through three SAD samples pulls the fit towards the sample grid: at level pixels of 1.2 and 1.44,
// 0.135 / 0.153 px rms over every fractional shift; after the Gauss-Newton steps 0.048 / 0.038 px.
TEST(StereoRefinement, SubPixelFitIsNotPulledToTheSampleGrid) {
  const cv::Mat tex = blockTexture(3, 1.0);
  EpipolarPatchSearch parabola_only;
  parabola_only.gauss_newton_steps = 0;
  for (const double step : {1.2, 1.44}) {  // octaves 1 and 2
    double sum2[2] = {0.0, 0.0};
    int n = 0;
    for (int k = 0; k < 40; ++k) {
      const double shift = 4.0 + 0.05 * k;  // every fractional part of the level pixel
      cv::Mat shifted;
      const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, -shift, 0, 1, 0);
      cv::warpAffine(tex, shifted, M, tex.size(), cv::INTER_CUBIC);
      for (int j = 0; j < 10; ++j) {
        const Eigen::Vector2d ul(std::round((120.0 + 40.0 * j) / step) * step,
                                 std::round((100.0 + 25.0 * j) / step) * step);
        const Eigen::Vector2d ur_raw(std::round((ul.x() - shift) / step) * step, ul.y());
        Eigen::Vector2d ur, ur_parabola;
        ASSERT_TRUE(refineAlongEpipolar(tex, shifted, ul, ur_raw, Eigen::Vector2d(1, 0), step, &ur)) << step;
        ASSERT_TRUE(refineAlongEpipolar(tex, shifted, ul, ur_raw, Eigen::Vector2d(1, 0), step, &ur_parabola,
                                        parabola_only));
        sum2[0] += std::pow(ul.x() - ur.x() - shift, 2);
        sum2[1] += std::pow(ul.x() - ur_parabola.x() - shift, 2);
        ++n;
      }
    }
    const double rms = std::sqrt(sum2[0] / n), rms_parabola = std::sqrt(sum2[1] / n);
    std::printf("level pixel %.2f: disparity error rms %.3f px (the parabola's fit alone %.3f) over %d fits\n", step,
                rms, rms_parabola, n);
    EXPECT_LT(rms, 0.08) << "step " << step;
    EXPECT_GT(rms_parabola, 1.5 * rms) << "step " << step;
  }
}

// A surface seen at a slant (the road under a horizontal rig): the disparity grows down the image, by 0.2 px per
// row here (a 0.54 m baseline 2.7 m above the road gives 0.2), ~1.4 px over a patch at level pixel 1.44. With the
// texture strong in one half of the patch and faint in the other (a lane marking's edge, a kerb) one shift for the
// whole patch is pulled towards the strong half's disparity; the slanted fit keeps the disparity of the centre.
TEST(StereoRefinement, SlantedSurfaceKeepsTheDisparityOfThePatchCentre) {
  cv::Mat tex;
  blockTexture(5, 1.5).convertTo(tex, CV_32F);
  for (int v = 0; v < tex.rows; ++v) {  // bands of 20 rows: full contrast, then a fifth of it
    const float gain = (v / 20) % 2 == 0 ? 1.f : 0.2f;
    for (int u = 0; u < tex.cols; ++u) tex.at<float>(v, u) = 128.f + gain * (tex.at<float>(v, u) - 128.f);
  }
  tex.convertTo(tex, CV_8U);
  const double d0 = 20.0, slope = 0.2, v_ref = 240.0;  // right(u, v) = left(u + d0 + slope (v - v_ref), v)
  cv::Mat right;
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, slope, d0 - slope * v_ref, 0, 1, 0);
  cv::warpAffine(tex, right, M, tex.size(), cv::INTER_CUBIC | cv::WARP_INVERSE_MAP);
  EpipolarPatchSearch one_shift;
  one_shift.slanted = false;
  const double step = 1.44;  // octave 2
  double err[2] = {0.0, 0.0};
  int n = 0;
  for (int band = 4; band < 20; ++band) {  // patch centres on the bands' edges: one half strong, one faint
    for (int j = 0; j < 8; ++j) {
      const Eigen::Vector2d ul(100.0 + 60.0 * j + 0.37 * band, 20.0 * band);
      const double disparity = d0 + slope * (ul.y() - v_ref);
      const Eigen::Vector2d ur_raw(std::round(ul.x() - disparity), ul.y());
      Eigen::Vector2d ur, ur_one;
      ASSERT_TRUE(refineAlongEpipolar(tex, right, ul, ur_raw, Eigen::Vector2d(1, 0), step, &ur));
      ASSERT_TRUE(refineAlongEpipolar(tex, right, ul, ur_raw, Eigen::Vector2d(1, 0), step, &ur_one, one_shift));
      err[0] += std::abs(ul.x() - ur.x() - disparity);
      err[1] += std::abs(ul.x() - ur_one.x() - disparity);
      ++n;
    }
  }
  const double slanted = err[0] / n, flat = err[1] / n;
  std::printf("slanted surface: mean |disparity error| %.3f px (one shift for the patch: %.3f) over %d fits\n", slanted,
              flat, n);
  EXPECT_LT(slanted, 0.1);
  EXPECT_GT(flat, 3.0 * slanted);
}

// A plane 50 m away, EuRoC's focal length and baseline: ~1 px of disparity, quantized to the keypoints' level
// pixels. The raw matches that survive (in front of both cameras) are those whose disparity came out large (depths
// short); refined along the epipolar line the depths are right (one disparity for the whole plane: the sub-pixel
// fit's pull towards the sample grid would show as a bias).
TEST(StereoMatcher, FarPlaneDepthWithSubPixelRefinement) {
  auto cam = std::make_shared<TestPinhole>(752, 480, 458.0, 376.0, 240.0);
  StereoRig rig;
  rig.left = rig.right = cam;
  rig.T_r_l = Eigen::Isometry3d::Identity();
  rig.T_r_l.translation() = Eigen::Vector3d(-0.11, 0, 0);
  const double depth = 50.0, texel = 0.1;
  cv::Mat coarse(200, 300, CV_8UC1), tex;
  cv::RNG rng(7);
  rng.fill(coarse, cv::RNG::UNIFORM, 0, 255);
  cv::resize(coarse, tex, cv::Size(1200, 800), 0, 0, cv::INTER_NEAREST);  // 0.4 m blocks
  cv::GaussianBlur(tex, tex, cv::Size(0, 0), 1.5);
  const cv::Mat il = planeImage(tex, texel, *cam, depth, 0.0), ir = planeImage(tex, texel, *cam, depth, 0.11);
  EnhanceParams ep;
  FeatureParams fp;
  applyFrontEndMode(FrontEndMode::kIraf, &ep, &fp);
  FrontEnd fe_l(ep, fp, true), fe_r(ep, fp, true);  // with their images: the refinement
  const FeatureFrame fl = fe_l.process(il, 0.0), fr = fe_r.process(ir, 0.0);
  ASSERT_FALSE(fl.image.empty());
  TrackerParams p;
  p.stereo_min_disparity_px = 0.0;  // 1 px of disparity at 50 m: the refinement's precision, not the floor
  Frame left, right;
  ASSERT_NO_FATAL_FAILURE(toFrames(fl, fr, *cam, &left, &right));
  const StereoMatcher matcher(rig, p);
  auto depthErrors = [&](const std::vector<StereoMatch>& matches, double* median, double* mean) {
    std::vector<double> rel;
    for (const StereoMatch& m : matches) rel.push_back(m.p_l.z() / depth - 1.0);
    ASSERT_GE(rel.size(), 50u);
    std::sort(rel.begin(), rel.end());
    *median = rel[rel.size() / 2];
    *mean = 0.0;
    for (double r : rel) *mean += r / static_cast<double>(rel.size());
  };
  double med_raw, mean_raw, med, mean;
  const std::vector<StereoMatch> raw = matcher.match(left, right);
  const std::vector<StereoMatch> refined = matcher.match(left, right, fl.image, fr.image);
  depthErrors(raw, &med_raw, &mean_raw);
  depthErrors(refined, &med, &mean);
  std::printf("plane at %.0f m: raw %zu matches, depth error median %+.1f %% mean %+.1f %%; refined %zu matches, "
              "median %+.1f %% mean %+.1f %%\n", depth, raw.size(), 100 * med_raw, 100 * mean_raw, refined.size(),
              100 * med, 100 * mean);
  EXPECT_LT(std::abs(med), 0.01);  // -1.7 % with the parabola's fit alone
  EXPECT_LT(std::abs(mean), 0.02);  // +3.0 % with the parabola's fit alone
  for (const StereoMatch& m : refined) {  // the right observation is the refined pixel
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam->project(rig.T_r_l * m.p_l, &uv));
    EXPECT_LT((uv - m.uv_r).norm(), 0.5);
  }
}

// Far points (disparity below stereo_min_disparity_px) get no depth from one stereo frame: near the floor, only
// the matches whose disparity error was positive survive the depth range, so their depths come out short.
TEST(StereoMatcher, NoDepthBelowTheDisparityFloor) {
  for (const CameraModelPtr& cam : {CameraModelPtr(std::make_shared<TestPinhole>(640, 480, 450.0, 320.0, 240.0)),
                                   CameraModelPtr(std::make_shared<TestFisheye>(512, 512, 190.0, 256.0, 256.0))}) {
    const StereoRig rig = syntheticRig(cam);
    SyntheticWorld world;
    const double floor_depth = cam->focal() * rig.baseline() / 2.0;  // 2 px (default floor): 27 m / 11.4 m
    world.addBox(300, Eigen::Vector3d(-3, -2, 2.0), Eigen::Vector3d(3, 2, 0.5 * floor_depth));
    world.addBox(300, Eigen::Vector3d(-20, -10, 2.0 * floor_depth), Eigen::Vector3d(20, 10, 4.0 * floor_depth));
    const FeatureFrame fl = world.render(*cam, Eigen::Isometry3d::Identity(), 0.0, 0.3, 4);
    const FeatureFrame fr = world.render(*cam, rig.T_r_l.inverse(), 0.0, 0.3, 4);
    Frame left, right;
    ASSERT_NO_FATAL_FAILURE(toFrames(fl, fr, *cam, &left, &right));
    TrackerParams p;
    const StereoMatcher matcher(rig, p);
    EXPECT_NEAR(matcher.closeDepth(), floor_depth, 1e-9) << cam->modelName();
    int near = 0;
    for (const StereoMatch& m : matcher.match(left, right)) {
      EXPECT_LE(m.depth(), floor_depth) << cam->modelName();
      near += m.depth() < 0.5 * floor_depth + 1.0;
    }
    EXPECT_GT(near, 150) << cam->modelName();
    p.stereo_min_disparity_px = 0.0;  // off: the far box is matched too
    int far = 0;
    for (const StereoMatch& m : StereoMatcher(rig, p).match(left, right)) far += m.depth() > floor_depth;
    EXPECT_GT(far, 50) << cam->modelName();
  }
}

// A frame with few close matches: the nearest far ones fill it up to stereo_far_fill_points, whatever the start's
// minimum (stereo_init_min_points) is; 0 = no fill.
TEST(StereoMatcher, FarPointsFillUpToTheirOwnCount) {
  auto cam = std::make_shared<TestPinhole>(640, 480, 450.0, 320.0, 240.0);
  const StereoRig rig = syntheticRig(cam);
  SyntheticWorld world;
  const double floor_depth = cam->focal() * rig.baseline() / 2.0;  // 2 px: 27 m
  world.addBox(40, Eigen::Vector3d(-3, -2, 3.0), Eigen::Vector3d(3, 2, 0.3 * floor_depth));
  world.addBox(400, Eigen::Vector3d(-20, -10, 1.5 * floor_depth), Eigen::Vector3d(20, 10, 2.5 * floor_depth));
  Frame left, right;
  ASSERT_NO_FATAL_FAILURE(toFrames(world.render(*cam, Eigen::Isometry3d::Identity(), 0.0, 0.3, 4),
                                   world.render(*cam, rig.T_r_l.inverse(), 0.0, 0.3, 4), *cam, &left, &right));
  TrackerParams p;
  p.stereo_far_fill_points = 0;
  const size_t close = StereoMatcher(rig, p).match(left, right).size();
  EXPECT_GT(close, 20u);
  EXPECT_LT(close, 60u);
  for (int init_min : {8, 100}) {
    p.stereo_init_min_points = init_min;
    p.stereo_far_fill_points = 120;
    const std::vector<StereoMatch> m = StereoMatcher(rig, p).match(left, right);
    EXPECT_EQ(m.size(), 120u) << init_min;
    int far = 0;
    for (const StereoMatch& x : m) far += x.depth() > floor_depth;
    EXPECT_EQ(far, 120 - static_cast<int>(close)) << init_min;
  }
}

TEST(StereoMatcher, SyntheticPinholePair) {
  checkSyntheticPair(std::make_shared<TestPinhole>(640, 480, 450.0, 320.0, 240.0));
}

TEST(StereoMatcher, SyntheticFisheyePair) {
  checkSyntheticPair(std::make_shared<TestFisheye>(640, 640, 200.0, 320.0, 320.0));
}

TEST(StereoMatcher, NoMatchesWhenTheRightImageShowsOtherPoints) {
  auto cam = std::make_shared<TestPinhole>(640, 480, 450.0, 320.0, 240.0);
  const StereoRig rig = syntheticRig(cam);
  SyntheticWorld a, b;
  b.rng.seed(99);
  a.addBox(400, Eigen::Vector3d(-3, -2, 1.0), Eigen::Vector3d(3, 2, 4.5));
  b.addBox(400, Eigen::Vector3d(-3, -2, 1.0), Eigen::Vector3d(3, 2, 4.5));
  Frame left, right;
  std::string err;
  ASSERT_TRUE(Frame::fromFeatures(a.render(*cam, Eigen::Isometry3d::Identity(), 0.0), *cam, 0, &left, &err));
  ASSERT_TRUE(Frame::fromFeatures(b.render(*cam, rig.T_r_l.inverse(), 0.0), *cam, 0, &right, &err));
  TrackerParams p;
  EXPECT_LT(StereoMatcher(rig, p).match(left, right).size(), 5u);  // random descriptors: chance matches only
}

TEST(StereoMatcher, EurocFrameZero) {
  const std::string dir = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/";
  if (!std::ifstream(dir + "cam1/sensor.yaml")) GTEST_SKIP() << "no EuRoC cam1 at " << dir;
  StereoRig rig;
  std::string err;
  ASSERT_TRUE(loadStereoRig(dir + "cam0/sensor.yaml", dir + "cam1/sensor.yaml", &rig, &err)) << err;
  const std::string name = "1403636584763555584.png";
  cv::Mat il, ir;
  ASSERT_TRUE(readMono8(dir + "cam0/data/" + name, &il, &err) && readMono8(dir + "cam1/data/" + name, &ir, &err)) << err;
  EnhanceParams ep;
  FeatureParams fp;
  applyFrontEndMode(FrontEndMode::kIraf, &ep, &fp);
  FrontEnd fe_l(ep, fp), fe_r(ep, fp);
  const FeatureFrame fl = fe_l.process(il, 0.0), fr = fe_r.process(ir, 0.0);
  TrackerParams p;
  Frame left, right;
  ASSERT_TRUE(Frame::fromFeatures(fl, *rig.left, 0, &left, &err)) << err;
  ASSERT_TRUE(Frame::fromFeatures(fr, *rig.right, 0, &right, &err)) << err;
  const std::vector<StereoMatch> matches = StereoMatcher(rig, p).match(left, right);
  std::vector<double> depth;
  for (const StereoMatch& m : matches) depth.push_back(m.depth());
  std::sort(depth.begin(), depth.end());
  ASSERT_GE(matches.size(), 250u) << "of " << left.size() << " / " << right.size() << " keypoints";
  const double median = depth[depth.size() / 2];
  std::printf("EuRoC frame 0: %zu stereo matches of %zu / %zu keypoints; depth p10 %.2f median %.2f p90 %.2f m\n",
              matches.size(), left.size(), right.size(), depth[depth.size() / 10], median,
              depth[depth.size() * 9 / 10]);
  // The machine hall at frame 0: ~1-10 m away (up to stereo_max_depth_baselines x 0.11 m here).
  EXPECT_GT(median, 1.5);
  EXPECT_LT(depth.back(), 0.11 * p.stereo_max_depth_baselines + 0.01);
}
