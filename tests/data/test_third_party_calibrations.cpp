// Every calibration file that ships with OpenVINS (config/*/kalibr_*.yaml), VINS-Fusion and
// VINS-Mono (config/), and Basalt (data/*_calib.json), read by data::readCalibrationFiles, with
// values checked against what their authors wrote (copied by hand from the files). Their files
// are not in this repository: scripts/export_third_party_calibrations.sh exports them from git
// snapshots of the four repositories into a folder named by $ADUGS_THIRD_PARTY_CALIB; without it
// these tests skip with that hint.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include <Eigen/LU>

#include "data/formats/calibration_files.h"
#include "data/input_error.h"

namespace adugs::data {
namespace {
namespace fs = std::filesystem;

fs::path thirdParty(const std::string& tool) {
  const char* dir = std::getenv("ADUGS_THIRD_PARTY_CALIB");
  return dir ? fs::path(dir) / tool : fs::path();
}

#define REQUIRE_TOOL(tool)                                                                                  \
  const fs::path root = thirdParty(tool);                                                                   \
  if (root.empty() || !fs::is_directory(root))                                                              \
  GTEST_SKIP() << tool << "'s files are not here: run scripts/export_third_party_calibrations.sh OUT "      \
                          "<git dirs> and set ADUGS_THIRD_PARTY_CALIB=OUT"

RigCalibration read(const std::vector<fs::path>& files) {
  std::vector<std::string> paths;
  for (const fs::path& f : files) paths.push_back(f.string());
  return readCalibrationFiles(paths);
}

TEST(ThirdPartyCalibrations, EveryOpenVinsPairIsReadWithItsValues) {
  REQUIRE_TOOL("open_vins");
  int pairs = 0;
  for (const auto& entry : fs::directory_iterator(root / "config")) {
    const fs::path chain = entry.path() / "kalibr_imucam_chain.yaml", imu = entry.path() / "kalibr_imu_chain.yaml";
    if (!fs::exists(chain)) continue;
    SCOPED_TRACE(entry.path().filename().string());
    RigCalibration rig;
    ASSERT_NO_THROW(rig = read({chain, imu}));
    ++pairs;
    EXPECT_GE(rig.cameras.size(), 1u);
    EXPECT_TRUE(rig.has_imu);
    for (const RigCamera& c : rig.cameras) EXPECT_TRUE(c.has_T_imu_cam);
    EXPECT_TRUE(rig.imu.intrinsics.isIdentity());  // all ship Tw = Ta = I, Tg = 0
  }
  EXPECT_EQ(pairs, 14);

  const fs::path c = root / "config";
  RigCalibration euroc = read({c / "euroc_mav/kalibr_imucam_chain.yaml", c / "euroc_mav/kalibr_imu_chain.yaml"});
  ASSERT_EQ(euroc.cameras.size(), 2u);
  EXPECT_EQ(euroc.cameras[0].camera.fx, 458.654);
  EXPECT_EQ(euroc.cameras[0].camera.cy, 248.375);
  EXPECT_EQ(euroc.cameras[0].camera.distortion_model, DistortionModel::kRadialTangential);
  EXPECT_EQ(euroc.imu.noise.gyro_noise_density, 1.6968e-04);
  // T_imu_cam row 0 of cam0: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975]
  EXPECT_NEAR(euroc.cameras[0].camera.T_B_C(0, 3), -0.0216401454975, 1e-12);
  EXPECT_NEAR(euroc.cameras[0].camera.T_B_C(0, 1), -0.999880929698, 1e-6);

  RigCalibration tumvi = read({c / "tum_vi/kalibr_imucam_chain.yaml", c / "tum_vi/kalibr_imu_chain.yaml"});
  EXPECT_EQ(tumvi.cameras[0].camera.distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(tumvi.cameras[0].camera.fx, 190.97847715128717);
  EXPECT_EQ(tumvi.cameras[0].camera.width, 512);
  EXPECT_EQ(tumvi.imu.noise.gyro_noise_density, 0.00016);
  // T_cam_imu row 0: [-0.9995250378696743, 0.029615343885863205, -0.008522328211654736, 0.04727988224914392]
  EXPECT_NEAR(tumvi.cameras[0].camera.T_B_C.inverse()(0, 3), 0.04727988224914392, 1e-12);

  RigCalibration kaist = read({c / "kaist/kalibr_imucam_chain.yaml", c / "kaist/kalibr_imu_chain.yaml"});
  EXPECT_EQ(kaist.cameras[0].camera.fx, 8.1690378992770002e+02);
  EXPECT_EQ(kaist.imu.noise.accel_noise_density, 5.8860e-03);
  EXPECT_EQ(kaist.imu.noise.rate_hz, 500.0);

  RigCalibration kaist_vio = read({c / "kaist_vio/kalibr_imucam_chain.yaml", c / "kaist_vio/kalibr_imu_chain.yaml"});
  EXPECT_EQ(kaist_vio.cameras[0].time_offset_s, -0.029958533056650416);
  EXPECT_NEAR(kaist_vio.cameras[0].camera.T_B_C.inverse()(2, 3), -0.1363488241088845, 1e-12);

  RigCalibration d455 = read({c / "rs_d455/kalibr_imucam_chain.yaml", c / "rs_d455/kalibr_imu_chain.yaml"});
  ASSERT_EQ(d455.cameras.size(), 1u);
  EXPECT_EQ(d455.cameras[0].camera.fx, 416.85223429743274);
  EXPECT_EQ(d455.cameras[0].time_offset_s, 0.002524377913673846);
  EXPECT_EQ(d455.imu.noise.gyro_noise_density, 0.00020544166);

  RigCalibration t265 = read({c / "rs_t265/kalibr_imucam_chain.yaml", c / "rs_t265/kalibr_imu_chain.yaml"});
  EXPECT_EQ(t265.cameras[0].camera.fx, 282.019963259348);
  EXPECT_EQ(t265.imu.noise.gyro_noise_density, 0.00054166825);

  RigCalibration sim = read({c / "rpng_sim/kalibr_imucam_chain.yaml", c / "rpng_sim/kalibr_imu_chain.yaml"});
  EXPECT_EQ(sim.cameras.size(), 4u);

  RigCalibration fpv = read({c / "uzhfpv_indoor/kalibr_imucam_chain.yaml", c / "uzhfpv_indoor/kalibr_imu_chain.yaml"});
  EXPECT_EQ(fpv.cameras[0].camera.fx, 278.66723066149086);
  EXPECT_EQ(fpv.cameras[0].time_offset_s, -0.016684572091862235);
  EXPECT_EQ(fpv.cameras[0].rostopic, "/snappy_cam/stereo_l");
}

TEST(ThirdPartyCalibrations, EveryVinsFusionConfigIsReadWithItsCameraFiles) {
  REQUIRE_TOOL("VINS-Fusion");
  int configs = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root / "config")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    RigCalibration rig;
    ASSERT_NO_THROW(rig = read({entry.path()}));
    EXPECT_GE(rig.cameras.size(), 1u);
    ++configs;
  }
  EXPECT_GE(configs, 40);
  const fs::path c = root / "config";
  RigCalibration euroc = read({c / "euroc/euroc_mono_imu_config.yaml"});
  ASSERT_EQ(euroc.cameras.size(), 1u);
  EXPECT_EQ(euroc.cameras[0].camera.projection, ProjectionModel::kUnified);
  EXPECT_EQ(euroc.cameras[0].camera.projection_params[0], 3.6313355285286337e+00);
  EXPECT_EQ(euroc.cameras[0].camera.fx, 2.1387619122017772e+03);
  EXPECT_EQ(euroc.cameras[0].camera.distortion[1], 1.5491281051140213e+01);
  EXPECT_NEAR(euroc.cameras[0].camera.T_B_C(0, 3), -0.0216401454975, 1e-12);
  EXPECT_EQ(euroc.imu.noise.accel_noise_density, 0.1);
  EXPECT_TRUE(euroc.imu.noise_per_sample);

  RigCalibration d435i = read({c / "realsense_d435i/realsense_stereo_imu_config.yaml"});
  ASSERT_EQ(d435i.cameras.size(), 2u);
  EXPECT_EQ(d435i.cameras[0].camera.fx, 385.7544860839844);
  EXPECT_EQ(d435i.cameras[0].camera.width, 640);
  EXPECT_NEAR(d435i.cameras[0].camera.T_B_C(0, 3), 2.0329267950355900e-02, 1e-15);
  EXPECT_NEAR(d435i.cameras[1].camera.T_B_C(1, 3), -5.2435791444330505e-02, 1e-15);
  EXPECT_EQ(d435i.cameras[0].rostopic, "/camera/infra1/image_rect_raw");
  EXPECT_EQ(d435i.imu.noise.gyro_random_walk, 0.0001);
}

TEST(ThirdPartyCalibrations, EveryVinsMonoConfigIsRead) {
  REQUIRE_TOOL("VINS-Mono");
  int configs = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root / "config")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    RigCalibration rig;
    ASSERT_NO_THROW(rig = read({entry.path()}));
    // simulation_config.yaml (its data generator's) names no camera model: its extrinsic is listed.
    EXPECT_EQ(rig.cameras.size(), entry.path().filename() == "simulation_config.yaml" ? 0u : 1u);
    ++configs;
  }
  EXPECT_GE(configs, 9);
  RigCalibration euroc = read({root / "config/euroc/euroc_config.yaml"});
  EXPECT_EQ(euroc.cameras[0].camera.fx, 4.616e+02);
  EXPECT_EQ(euroc.cameras[0].camera.distortion[0], -2.917e-01);
  EXPECT_EQ(euroc.imu.noise.accel_noise_density, 0.08);
  EXPECT_NEAR(euroc.cameras[0].camera.T_B_C(1, 3), -0.064676986768, 1e-12);
  RigCalibration fisheye = read({root / "config/realsense/realsense_fisheye_config.yaml"});
  EXPECT_EQ(fisheye.cameras[0].camera.distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(fisheye.cameras[0].camera.distortion[0], 1.7280355035195181e-02);
  EXPECT_EQ(fisheye.cameras[0].camera.fx, 2.7723712054408202e+02);
}

TEST(ThirdPartyCalibrations, EveryBasaltCalibrationIsReadWithItsValues) {
  REQUIRE_TOOL("basalt");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(root / "data")) {
    const std::string name = entry.path().filename().string();
    if (name.find("_calib.json") == std::string::npos) continue;
    SCOPED_TRACE(name);
    RigCalibration rig;
    ASSERT_NO_THROW(rig = read({entry.path()}));
    EXPECT_EQ(rig.cameras.size(), 2u);
    EXPECT_TRUE(rig.has_imu);
    ++files;
  }
  EXPECT_EQ(files, 5);
  const fs::path d = root / "data";
  RigCalibration ds = read({d / "euroc_ds_calib.json"});
  EXPECT_EQ(ds.cameras[0].camera.projection, ProjectionModel::kDoubleSphere);
  EXPECT_EQ(ds.cameras[0].camera.projection_params, (std::vector<double>{-0.2409573942178872, 0.566996899163044}));
  EXPECT_EQ(ds.cameras[0].camera.fx, 349.7560023050409);
  EXPECT_EQ(ds.cameras[0].camera.width, 752);
  EXPECT_NEAR(ds.cameras[0].camera.T_B_C.translation().x(), -0.016774788924641534, 1e-15);
  EXPECT_EQ(ds.imu.noise.accel_noise_density, 0.016);
  EXPECT_EQ(ds.imu.noise.gyro_noise_density, 0.000282);
  EXPECT_EQ(ds.imu.noise.rate_hz, 200.0);
  RigCalibration eucm = read({d / "euroc_eucm_calib.json"});
  EXPECT_EQ(eucm.cameras[0].camera.projection, ProjectionModel::kExtendedUnified);
  EXPECT_EQ(eucm.cameras[0].camera.projection_params, (std::vector<double>{0.5903365915227143, 1.127468196965374}));
  EXPECT_EQ(eucm.cameras[0].camera.fx, 460.76484651566468);
  RigCalibration kb4 = read({d / "t265_kb4_calib.json"});
  EXPECT_EQ(kb4.cameras[0].camera.distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(kb4.cameras[0].camera.distortion[0], -0.006762412326815424);
  EXPECT_EQ(kb4.cameras[0].camera.fx, 286.60144163375528);
  // Its accelerometer scale [s1..s6] = [0.016180888150195365, -0.01147187471851237, ...]: Ta^-1 = I + S.
  const Eigen::Matrix3d Sa = kb4.imu.intrinsics.Ta.inverse() - Eigen::Matrix3d::Identity();
  EXPECT_NEAR(Sa(0, 0), 0.016180888150195365, 1e-12);
  EXPECT_NEAR(Sa(1, 0), -0.01147187471851237, 1e-12);
  EXPECT_NEAR(Sa(2, 2), 0.016344294616207294, 1e-12);
  EXPECT_NEAR(Sa(0, 1), 0.0, 1e-15);
  // Gyroscope [s1..s9] column by column: S(1, 0) = s2 = -0.003948783740038318, S(0, 1) = s4.
  const Eigen::Matrix3d Sg = kb4.imu.intrinsics.Tw.inverse() - Eigen::Matrix3d::Identity();
  EXPECT_NEAR(Sg(0, 0), -0.001501459772989326, 1e-12);
  EXPECT_NEAR(Sg(1, 0), -0.003948783740038318, 1e-12);
  EXPECT_NEAR(Sg(0, 1), 0.0026019412599533719, 1e-12);
  RigCalibration tumvi = read({d / "tumvi_512_ds_calib.json"});
  EXPECT_EQ(tumvi.cameras[0].camera.projection_params[0], -0.17213086034353243);
  RigCalibration tumvi_eucm = read({d / "tumvi_512_eucm_calib.json"});
  EXPECT_EQ(tumvi_eucm.cameras[0].camera.fx, 191.14799836282189);
  EXPECT_EQ(tumvi_eucm.cameras[0].camera.projection_params[0], 0.6291060881178562);
}

}  // namespace
}  // namespace adugs::data
