// StereoRig: T_r_l and the baseline from two camera yaml files (EuRoC cam0 + cam1), and the errors that name the
// file or the problem.
#include <gtest/gtest.h>

#include <fstream>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/camera/stereo_rig.h"

using namespace iraf_vo;

#include "common/tmp_dir.h"

namespace {

const std::string kEuroc = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/";

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = tmpRoot() + name;
  std::ofstream(path) << text;
  return path;
}

std::string cameraYaml(const std::string& t_bs_row1) {
  return "camera_model: pinhole\nintrinsics: [400, 400, 320, 240]\ndistortion_model: radial-tangential\n"
         "distortion_coefficients: [0, 0, 0, 0]\nresolution: [640, 480]\n"
         "T_BS:\n  rows: 4\n  cols: 4\n  data: [1, 0, 0, " + t_bs_row1 + ", 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n";
}

}  // namespace

TEST(StereoRig, EurocCam0Cam1BaselineAndTransform) {
  if (!std::ifstream(kEuroc + "cam1/sensor.yaml")) GTEST_SKIP() << "no EuRoC cam1 at " << kEuroc;
  StereoRig rig;
  std::string err;
  ASSERT_TRUE(loadStereoRig(kEuroc + "cam0/sensor.yaml", kEuroc + "cam1/sensor.yaml", &rig, &err)) << err;
  EXPECT_NEAR(rig.baseline(), 0.110, 0.0005);
  // cam1 sits to the right of cam0 (+x of the left optical frame): p_r = T_r_l p_l moves points to -x.
  EXPECT_LT(rig.T_r_l.translation().x(), -0.109);
  EXPECT_LT(std::abs(rig.T_r_l.translation().y()), 0.01);
  EXPECT_LT(Eigen::AngleAxisd(rig.T_r_l.linear()).angle(), 0.02);  // the two cameras are nearly parallel (0.8 deg)
  EXPECT_TRUE(validate(rig).empty());
}

TEST(StereoRig, SyntheticPairGivesTheTranslationBetweenTheBodies) {
  StereoRig rig;
  std::string err;
  const std::string l = writeFile("l.yaml", cameraYaml("0")), r = writeFile("r.yaml", cameraYaml("0.25"));
  ASSERT_TRUE(loadStereoRig(l, r, &rig, &err)) << err;
  EXPECT_NEAR(rig.baseline(), 0.25, 1e-12);
  EXPECT_NEAR(rig.T_r_l.translation().x(), -0.25, 1e-12);
}

TEST(StereoRig, ErrorsNameTheFileOrTheProblem) {
  StereoRig rig;
  std::string err;
  const std::string good = writeFile("good.yaml", cameraYaml("0"));
  EXPECT_FALSE(loadStereoRig(good, tmpRoot() + "missing_right.yaml", &rig, &err));
  EXPECT_NE(err.find("missing_right.yaml"), std::string::npos) << err;
  EXPECT_NE(err.find("right camera"), std::string::npos) << err;
  const std::string garbled = writeFile("garbled.yaml", "camera_model: [unclosed\n");
  EXPECT_FALSE(loadStereoRig(garbled, good, &rig, &err));
  EXPECT_NE(err.find("garbled.yaml"), std::string::npos) << err;
  EXPECT_NE(err.find("left camera"), std::string::npos) << err;
  // The same T_BS twice: baseline 0.
  EXPECT_FALSE(loadStereoRig(good, good, &rig, &err));
  EXPECT_NE(err.find("baseline 0"), std::string::npos) << err;
  StereoRig half;
  half.left = loadCamera(good, &err);
  EXPECT_NE(validate(half).find("right camera is missing"), std::string::npos);
}
