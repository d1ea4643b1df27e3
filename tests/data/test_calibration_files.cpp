// The calibration files of other tools (data/formats/calibration_files.h): hand-written files in
// each format with the values checked one by one, the errors, IMU intrinsics, and read -> write ->
// read round trips for every writer. The files shipped with OpenVINS, VINS and Basalt are read in
// test_third_party_calibrations.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "data/formats/calibration_files.h"
#include "data/formats/calibration_writers.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

using test::TempDir;
using test::writeText;

std::string errorOf(const std::vector<std::string>& files) {
  try {
    readCalibrationFiles(files);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// Kalibr's documented IMU input (its wiki's imu.yaml): flat keys.
TEST(CalibrationFiles, KalibrFlatImuFile) {
  TempDir dir;
  writeText(dir / "imu.yaml",
            "#Accelerometers\naccelerometer_noise_density: 1.86e-03\naccelerometer_random_walk: 4.33e-04\n"
            "#Gyroscopes\ngyroscope_noise_density: 1.87e-04\ngyroscope_random_walk: 2.66e-05\n"
            "rostopic: /imu0\nupdate_rate: 200.0\n");
  const RigCalibration rig = readCalibrationFiles({(dir / "imu.yaml").string()});
  ASSERT_TRUE(rig.has_imu);
  EXPECT_TRUE(rig.cameras.empty());
  EXPECT_EQ(rig.imu.noise.accel_noise_density, 1.86e-03);
  EXPECT_EQ(rig.imu.noise.accel_random_walk, 4.33e-04);
  EXPECT_EQ(rig.imu.noise.gyro_noise_density, 1.87e-04);
  EXPECT_EQ(rig.imu.noise.gyro_random_walk, 2.66e-05);
  EXPECT_EQ(rig.imu.noise.rate_hz, 200.0);
  EXPECT_EQ(rig.imu.rostopic, "/imu0");
  EXPECT_EQ(rig.formats.front(), "Kalibr imu (flat)");
  EXPECT_TRUE(rig.imu.intrinsics.isIdentity());
}

// Kalibr's results (imu0: with the scale-misalignment blocks) are applied, not dropped.
TEST(CalibrationFiles, KalibrImuResultsWithScaleMisalignment) {
  TempDir dir;
  writeText(dir / "results-imu.yaml",
            "imu0:\n  T_i_b:\n  - [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]\n"
            "  - [0.0, 0.0, 0.0, 1.0]\n  accelerometer_noise_density: 0.01\n  accelerometer_random_walk: 0.0002\n"
            "  gyroscope_noise_density: 0.005\n  gyroscope_random_walk: 4.0e-06\n  model: scale-misalignment\n"
            "  rostopic: /imu0\n  time_offset: 0.0\n  update_rate: 400.0\n"
            "  gyroscopes:\n    M:\n    - [1.0, 0.0, 0.0]\n    - [0.0, 2.0, 0.0]\n    - [0.0, 0.0, 1.0]\n"
            "    A:\n    - [0.0, 0.0, 0.0]\n    - [0.0, 0.0, 0.0]\n    - [0.5, 0.0, 0.0]\n"
            "    C_gyro_i:\n    - [0.0, -1.0, 0.0]\n    - [1.0, 0.0, 0.0]\n    - [0.0, 0.0, 1.0]\n"
            "  accelerometers:\n    M:\n    - [2.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0]\n    - [0.0, 0.0, 1.0]\n");
  const RigCalibration rig = readCalibrationFiles({(dir / "results-imu.yaml").string()});
  ASSERT_TRUE(rig.has_imu);
  const ImuIntrinsics& in = rig.imu.intrinsics;
  EXPECT_FALSE(in.isIdentity());
  // Worked by hand: the sample of a true w = (2, -1, 1), a = (1, 0, 0) is, by the model
  // w_meas = Tw R w + Tg a = (1, 4, 1) + (0, 0, 0.5) and a_meas = Ta a = (2, 0, 0).
  Eigen::Vector3d gyro(1, 4, 1.5), accel(2, 0, 0);
  in.correct(gyro, accel);
  EXPECT_TRUE(accel.isApprox(Eigen::Vector3d(1, 0, 0), 1e-12)) << accel.transpose();
  EXPECT_TRUE(gyro.isApprox(Eigen::Vector3d(2, -1, 1), 1e-12)) << gyro.transpose();
}

TEST(CalibrationFiles, KalibrSizeEffectModelIsRefusedNamingTheKey) {
  TempDir dir;
  writeText(dir / "imu.yaml",
            "imu0:\n  accelerometer_noise_density: 0.01\n  accelerometer_random_walk: 0.0002\n"
            "  gyroscope_noise_density: 0.005\n  gyroscope_random_walk: 4.0e-06\n"
            "  model: scale-misalignment-size-effect\n");
  const std::string e = errorOf({(dir / "imu.yaml").string()});
  EXPECT_NE(e.find("imu0.model"), std::string::npos) << e;
  EXPECT_NE(e.find("size-effect"), std::string::npos) << e;
}

// OpenVINS writes T_imu_cam (camera -> IMU) and the IMU intrinsics as Tw, Ta, Tg; its files start
// with OpenCV's "%YAML:1.0". Keys that change nothing are listed, never an error.
TEST(CalibrationFiles, OpenVinsVariantWithTImuCamAndIntrinsics) {
  TempDir dir;
  writeText(dir / "kalibr_imucam_chain.yaml",
            "%YAML:1.0 # need to specify the file type at the top!\n\ncam0:\n"
            "  T_imu_cam: #rotation from camera to IMU R_CtoI, position of camera in IMU p_CinI\n"
            "    - [0.0, -1.0, 0.0, 0.1]\n    - [1.0, 0.0, 0.0, 0.2]\n    - [0.0, 0.0, 1.0, 0.3]\n"
            "    - [0.0, 0.0, 0.0, 1.0]\n  cam_overlaps: [1]\n  camera_model: pinhole\n"
            "  distortion_coeffs: [-0.28, 0.07, 0.0002, 1.8e-05]\n  distortion_model: radtan\n"
            "  intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv\n  resolution: [752, 480]\n"
            "  rostopic: /cam0/image_raw\n  timeshift_cam_imu: 0.004\n");
  writeText(dir / "kalibr_imu_chain.yaml",
            "%YAML:1.0\n\nimu0:\n  accelerometer_noise_density: 2.0e-3\n  accelerometer_random_walk: 3.0e-3\n"
            "  gyroscope_noise_density: 1.6968e-04\n  gyroscope_random_walk: 1.9393e-05\n  rostopic: /imu0\n"
            "  time_offset: 0.0\n  update_rate: 200.0\n  model: \"kalibr\"\n"
            "  Tw:\n    - [ 1.0, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
            "  R_IMUtoGYRO:\n    - [ 1.0, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
            "  Ta:\n    - [ 1.01, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
            "  R_IMUtoACC:\n    - [ 1.0, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
            "  Tg:\n    - [ 0.0, 0.0, 0.0 ]\n    - [ 0.0, 0.0, 0.0 ]\n    - [ 0.0, 0.0, 0.0 ]\n"
            "  lever_arm_note: 1\n");
  const RigCalibration rig =
      readCalibrationFiles({(dir / "kalibr_imucam_chain.yaml").string(), (dir / "kalibr_imu_chain.yaml").string()});
  ASSERT_EQ(rig.cameras.size(), 1u);
  const CameraCalibration& c = rig.cameras[0].camera;
  EXPECT_EQ(c.fx, 458.654);
  EXPECT_EQ(c.cy, 248.375);
  EXPECT_EQ(c.distortion, (std::vector<double>{-0.28, 0.07, 0.0002, 1.8e-05}));
  EXPECT_TRUE(rig.cameras[0].has_T_imu_cam);
  // T_imu_cam is T_B_C itself: the camera's x axis is the IMU's y axis, its origin at (0.1, 0.2, 0.3).
  EXPECT_TRUE(c.T_B_C.translation().isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE(c.T_B_C.rotation().col(0).isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_EQ(rig.cameras[0].time_offset_s, 0.004);
  ASSERT_TRUE(rig.has_imu);
  EXPECT_EQ(rig.imu.noise.gyro_random_walk, 1.9393e-05);
  EXPECT_EQ(rig.imu.intrinsics.Ta(0, 0), 1.01);
  EXPECT_FALSE(rig.imu.intrinsics.isIdentity());
  const std::string imu_file = (dir / "kalibr_imu_chain.yaml").string();
  EXPECT_TRUE(contains(rig.ignored_keys, imu_file + ": imu0.lever_arm_note")) << rig.ignored_keys.size();
  const std::string cam_file = (dir / "kalibr_imucam_chain.yaml").string();
  EXPECT_TRUE(contains(rig.ignored_keys, cam_file + ": cam0.cam_overlaps") ||
              !contains(rig.ignored_keys, cam_file + ": cam0.camera_model"));
}

TEST(CalibrationFiles, KalibrStereoChainAndItsCameraModels) {
  TempDir dir;
  // cam1 is an omni (MEI) camera without T_cam_imu: placed through T_cn_cnm1 (a 0.1 m baseline).
  writeText(dir / "camchain-imucam.yaml",
            "cam0:\n  T_cam_imu:\n  - [1, 0, 0, 0]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n"
            "  camera_model: ds\n  intrinsics: [-0.2, 0.57, 350, 349, 366, 249]\n  distortion_model: none\n"
            "  distortion_coeffs: []\n  resolution: [752, 480]\n"
            "cam1:\n  T_cn_cnm1:\n  - [1, 0, 0, -0.1]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n"
            "  camera_model: omni\n  intrinsics: [0.8, 700, 701, 376, 240]\n  distortion_model: radtan\n"
            "  distortion_coeffs: [-0.1, 0.01, 0, 0]\n  resolution: [752, 480]\n");
  const RigCalibration rig = readCalibrationFiles({(dir / "camchain-imucam.yaml").string()});
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_EQ(rig.cameras[0].camera.projection, ProjectionModel::kDoubleSphere);
  EXPECT_EQ(rig.cameras[0].camera.projection_params, (std::vector<double>{-0.2, 0.57}));
  EXPECT_EQ(rig.cameras[0].camera.fx, 350);
  EXPECT_EQ(rig.cameras[0].camera.distortion_model, DistortionModel::kNone);
  EXPECT_EQ(rig.cameras[1].camera.projection, ProjectionModel::kUnified);
  EXPECT_EQ(rig.cameras[1].camera.projection_params, (std::vector<double>{0.8}));
  EXPECT_EQ(rig.cameras[1].camera.fx, 700);
  EXPECT_TRUE(rig.cameras[1].has_T_imu_cam);
  // p_cam1 = p_cam0 - (0.1, 0, 0): cam1's origin is at x = +0.1 in cam0 (= IMU) coordinates.
  EXPECT_TRUE(rig.cameras[1].camera.T_B_C.translation().isApprox(Eigen::Vector3d(0.1, 0, 0)));
}

TEST(CalibrationFiles, VinsFusionConfigWithItsCameraFiles) {
  TempDir dir;
  writeText(dir / "left.yaml",
            "%YAML:1.0\n---\nmodel_type: PINHOLE\ncamera_name: camera\nimage_width: 640\nimage_height: 480\n"
            "distortion_parameters:\n   k1: 0.01\n   k2: -0.02\n   p1: 0.003\n   p2: -0.004\n"
            "projection_parameters:\n   fx: 385.75\n   fy: 385.5\n   cx: 323.12\n   cy: 236.74\n");
  writeText(dir / "right.yaml",
            "%YAML:1.0\n---\nmodel_type: MEI\ncamera_name: camera\nimage_width: 640\nimage_height: 480\n"
            "mirror_parameters:\n   xi: 2.5\ndistortion_parameters:\n   k1: 0.1\n   k2: 1.5\n   p1: 0.0\n   p2: 0.0\n"
            "projection_parameters:\n   gamma1: 1200.0\n   gamma2: 1201.0\n   u0: 320.0\n   v0: 240.0\n");
  writeText(dir / "config.yaml",
            "%YAML:1.0\n\nimu: 1\nnum_of_cam: 2\nimu_topic: \"/camera/imu\"\nimage0_topic: \"/camera/infra1/image_rect_raw\"\n"
            "image1_topic: \"/camera/infra2/image_rect_raw\"\noutput_path: \"/home/dji/output/\"\n"
            "cam0_calib: \"left.yaml\"\ncam1_calib: \"right.yaml\"\nimage_width: 640\nimage_height: 480\n"
            "estimate_extrinsic: 1\nbody_T_cam0: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n"
            "   data: [ 0., 0., 1., 0.02, -1., 0., 0., 0.008, 0., -1., 0., 0.003, 0., 0., 0., 1. ]\n"
            "body_T_cam1: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n"
            "   data: [ 0., 0., 1., 0.02, -1., 0., 0., -0.042, 0., -1., 0., 0.003, 0., 0., 0., 1. ]\n"
            "max_cnt: 150\nacc_n: 0.1\ngyr_n: 0.01\nacc_w: 0.001\ngyr_w: 0.0001\ng_norm: 9.805\n"
            "estimate_td: 1\ntd: 0.002\n");
  const RigCalibration rig = readCalibrationFiles({(dir / "config.yaml").string()});
  ASSERT_EQ(rig.cameras.size(), 2u);
  const CameraCalibration& l = rig.cameras[0].camera;
  EXPECT_EQ(l.fx, 385.75);
  EXPECT_EQ(l.fy, 385.5);
  EXPECT_EQ(l.distortion, (std::vector<double>{0.01, -0.02, 0.003, -0.004}));
  EXPECT_TRUE(l.T_B_C.translation().isApprox(Eigen::Vector3d(0.02, 0.008, 0.003)));
  EXPECT_TRUE(l.T_B_C.rotation().col(2).isApprox(Eigen::Vector3d(1, 0, 0)));  // optical axis = IMU x
  EXPECT_EQ(rig.cameras[0].time_offset_s, 0.002);
  EXPECT_EQ(rig.cameras[0].rostopic, "/camera/infra1/image_rect_raw");
  const CameraCalibration& r = rig.cameras[1].camera;
  EXPECT_EQ(r.projection, ProjectionModel::kUnified);
  EXPECT_EQ(r.projection_params, (std::vector<double>{2.5}));
  EXPECT_EQ(r.fx, 1200.0);
  EXPECT_EQ(r.cy, 240.0);
  EXPECT_EQ(r.distortion[1], 1.5);
  ASSERT_TRUE(rig.has_imu);
  EXPECT_TRUE(rig.imu.noise_per_sample);
  EXPECT_EQ(rig.imu.noise.accel_noise_density, 0.1);
  // Per-sample standard deviations become densities at the IMU rate: 0.1 * sqrt(1 / 400 Hz) = 0.005.
  RigImu imu = rig.imu;
  resolvePerSampleNoise(imu, 400);
  EXPECT_NEAR(imu.noise.accel_noise_density, 0.005, 1e-15);
  EXPECT_NEAR(imu.noise.gyro_random_walk, 0.000005, 1e-18);
  EXPECT_EQ(rig.files.size(), 3u);
  EXPECT_TRUE(contains(rig.ignored_keys, (dir / "config.yaml").string() + ": max_cnt"));
}

TEST(CalibrationFiles, VinsMonoConfigWithTheCameraInsideAndKannalaBrandt) {
  TempDir dir;
  writeText(dir / "fisheye.yaml",
            "%YAML:1.0\n\nimu_topic: \"/camera/imu/data_raw\"\nimage_topic: \"/camera/fisheye/image_raw\"\n"
            "model_type: KANNALA_BRANDT\ncamera_name: camera\nimage_width: 640\nimage_height: 480\n"
            "projection_parameters:\n   k2: 1.7e-02\n   k3: -2.5e-02\n   k4: 2.2e-02\n   k5: -7.3e-03\n"
            "   mu: 277.2\n   mv: 276.9\n   u0: 336.2\n   v0: 236.0\n"
            "estimate_extrinsic: 1\nextrinsicRotation: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
            "   data: [0, -1, 0, 1, 0, 0, 0, 0, 1]\nextrinsicTranslation: !!opencv-matrix\n   rows: 3\n   cols: 1\n"
            "   dt: d\n   data: [0.01, 0.02, 0.03]\nacc_n: 0.2\ngyr_n: 0.05\nacc_w: 0.02\ngyr_w: 4.0e-5\ntd: 0.0\n");
  const RigCalibration rig = readCalibrationFiles({(dir / "fisheye.yaml").string()});
  ASSERT_EQ(rig.cameras.size(), 1u);
  const CameraCalibration& c = rig.cameras[0].camera;
  EXPECT_EQ(c.distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(c.distortion, (std::vector<double>{1.7e-02, -2.5e-02, 2.2e-02, -7.3e-03}));
  EXPECT_EQ(c.fx, 277.2);
  EXPECT_EQ(c.cx, 336.2);
  EXPECT_TRUE(c.T_B_C.translation().isApprox(Eigen::Vector3d(0.01, 0.02, 0.03)));
  EXPECT_TRUE(c.T_B_C.rotation().col(0).isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_EQ(rig.imu.noise.gyro_noise_density, 0.05);
}

TEST(CalibrationFiles, BasaltJsonCamerasAndNoise) {
  TempDir dir;
  writeText(dir / "calib.json",
            "{\n \"value0\": {\n  \"T_imu_cam\": [\n"
            "   {\"px\": 0.1, \"py\": 0.2, \"pz\": 0.3, \"qx\": 0.0, \"qy\": 0.0, \"qz\": 0.7071067811865476, \"qw\": 0.7071067811865476},\n"
            "   {\"px\": -0.1, \"py\": 0.0, \"pz\": 0.0, \"qx\": 0.0, \"qy\": 0.0, \"qz\": 0.0, \"qw\": 1.0},\n"
            "   {\"px\": 0.0, \"py\": 0.0, \"pz\": 0.0, \"qx\": 0.0, \"qy\": 0.0, \"qz\": 0.0, \"qw\": 1.0}\n  ],\n"
            "  \"intrinsics\": [\n"
            "   {\"camera_type\": \"ds\", \"intrinsics\": {\"fx\": 349.7, \"fy\": 348.7, \"cx\": 365.8, \"cy\": 249.3, "
            "\"xi\": -0.24, \"alpha\": 0.567}},\n"
            "   {\"camera_type\": \"kb4\", \"intrinsics\": {\"fx\": 286.6, \"fy\": 286.4, \"cx\": 422.2, \"cy\": 395.2, "
            "\"k1\": -0.0067, \"k2\": 0.045, \"k3\": -0.0435, \"k4\": 0.0083}},\n"
            "   {\"camera_type\": \"unified\", \"intrinsics\": {\"fx\": 300, \"fy\": 300, \"cx\": 320, \"cy\": 240, \"alpha\": 0.6}}\n"
            "  ],\n  \"resolution\": [[752, 480], [848, 800], [640, 480]],\n"
            "  \"vignette\": [],\n  \"calib_accel_bias\": [-0.003, 0.12, 0.067, 0, 0, 0, 0, 0, 0],\n"
            "  \"calib_gyro_bias\": [-0.002, 0.02, 0.076, 0, 0, 0, 0, 0, 0, 0, 0, 0],\n"
            "  \"imu_update_rate\": 200.0,\n  \"accel_noise_std\": [0.016, 0.016, 0.018],\n"
            "  \"gyro_noise_std\": [0.000282, 0.000282, 0.000282],\n  \"accel_bias_std\": [0.001, 0.001, 0.001],\n"
            "  \"gyro_bias_std\": [0.0001, 0.0001, 0.0001],\n  \"cam_time_offset_ns\": 1500000\n }\n}\n");
  const RigCalibration rig = readCalibrationFiles({(dir / "calib.json").string()});
  ASSERT_EQ(rig.cameras.size(), 3u);
  const CameraCalibration& ds = rig.cameras[0].camera;
  EXPECT_EQ(ds.projection, ProjectionModel::kDoubleSphere);
  EXPECT_EQ(ds.projection_params, (std::vector<double>{-0.24, 0.567}));
  EXPECT_EQ(ds.fx, 349.7);
  EXPECT_EQ(ds.width, 752);
  EXPECT_TRUE(ds.T_B_C.translation().isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE(ds.T_B_C.rotation().col(0).isApprox(Eigen::Vector3d(0, 1, 0), 1e-12));  // 90 deg about z
  const CameraCalibration& kb = rig.cameras[1].camera;
  EXPECT_EQ(kb.distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(kb.distortion, (std::vector<double>{-0.0067, 0.045, -0.0435, 0.0083}));
  EXPECT_EQ(kb.height, 800);
  const CameraCalibration& ucm = rig.cameras[2].camera;  // Basalt's unified = EUCM with beta 1
  EXPECT_EQ(ucm.projection, ProjectionModel::kExtendedUnified);
  EXPECT_EQ(ucm.projection_params, (std::vector<double>{0.6, 1.0}));
  EXPECT_EQ(rig.cameras[0].time_offset_s, 0.0015);
  ASSERT_TRUE(rig.has_imu);
  EXPECT_EQ(rig.imu.noise.accel_noise_density, 0.018);  // the largest axis
  EXPECT_EQ(rig.imu.noise.gyro_random_walk, 0.0001);
  EXPECT_EQ(rig.imu.noise.rate_hz, 200.0);
  EXPECT_EQ(rig.formats.front(), "Basalt calibration JSON");
}

TEST(CalibrationFiles, ErrorsNameFileLineAndField) {
  TempDir dir;
  const std::string cam =
      "cam0:\n  camera_model: pinhole\n  intrinsics: [400, 401, 320, 240]\n  distortion_model: radtan\n"
      "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n";
  // A missing value.
  writeText(dir / "a.yaml", "cam0:\n  camera_model: pinhole\n  resolution: [640, 480]\n");
  std::string e = errorOf({(dir / "a.yaml").string()});
  EXPECT_NE(e.find("a.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("cam0.intrinsics"), std::string::npos) << e;
  // A value of the wrong type.
  writeText(dir / "b.yaml", cam + "  timeshift_cam_imu: soon\n");
  e = errorOf({(dir / "b.yaml").string()});
  EXPECT_NE(e.find("b.yaml:7"), std::string::npos) << e;
  EXPECT_NE(e.find("cam0.timeshift_cam_imu"), std::string::npos) << e;
  // A camera model the project cannot use.
  writeText(dir / "c.yaml", "%YAML:1.0\n---\nmodel_type: SCARAMUZZA\nimage_width: 640\nimage_height: 480\n"
                            "projection_parameters:\n   fx: 1\n");
  e = errorOf({(dir / "c.yaml").string()});
  EXPECT_NE(e.find("c.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("SCARAMUZZA"), std::string::npos) << e;
  // Two files that disagree: two different T_cam_imu.
  writeText(dir / "d1.yaml", cam + "  T_cam_imu:\n  - [1, 0, 0, 0.1]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n");
  writeText(dir / "d2.yaml", cam + "  T_cam_imu:\n  - [1, 0, 0, 0.2]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n");
  e = errorOf({(dir / "d1.yaml").string(), (dir / "d2.yaml").string()});
  EXPECT_NE(e.find("d2.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("d1.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("T_cam_imu"), std::string::npos) << e;
  // The same camera twice with and without the extrinsic is one camera (camchain + camchain-imucam).
  writeText(dir / "camchain.yaml", cam);
  const RigCalibration both = readCalibrationFiles({(dir / "camchain.yaml").string(), (dir / "d1.yaml").string()});
  ASSERT_EQ(both.cameras.size(), 1u);
  EXPECT_TRUE(both.cameras[0].has_T_imu_cam);
  EXPECT_NEAR(both.cameras[0].camera.T_B_C.translation().x(), -0.1, 1e-15);
  // Not a calibration file at all: its keys are listed.
  writeText(dir / "e.yaml", "max_features: 150\n");
  e = errorOf({(dir / "e.yaml").string()});
  EXPECT_NE(e.find("max_features"), std::string::npos) << e;
  EXPECT_NE(e.find("not a calibration file"), std::string::npos) << e;
  // A Basalt pose that is not a rotation.
  writeText(dir / "f.json",
            "{\"value0\": {\"T_imu_cam\": [{\"px\": 0, \"py\": 0, \"pz\": 0, \"qx\": 0, \"qy\": 0, \"qz\": 0, \"qw\": 2}],"
            " \"intrinsics\": [{\"camera_type\": \"pinhole\", \"intrinsics\": {\"fx\": 1, \"fy\": 1, \"cx\": 0, \"cy\": 0}}],"
            " \"resolution\": [[4, 4]]}}\n");
  e = errorOf({(dir / "f.json").string()});
  EXPECT_NE(e.find("T_imu_cam[0].qw"), std::string::npos) << e;
  // A missing file.
  e = errorOf({(dir / "missing.yaml").string()});
  EXPECT_NE(e.find("missing.yaml"), std::string::npos) << e;
}

// A rig every writer can hold some of: cameras chosen per tool.
RigCalibration rigFor(const std::string& tool) {
  RigCalibration rig;
  auto camera = [](ProjectionModel p, std::vector<double> params, DistortionModel d, std::vector<double> k, double tx) {
    RigCamera c;
    c.camera.width = 752;
    c.camera.height = 480;
    c.camera.fx = 458.654321;
    c.camera.fy = 457.296789;
    c.camera.cx = 367.215;
    c.camera.cy = 248.375;
    c.camera.projection = p;
    c.camera.projection_params = std::move(params);
    c.camera.distortion_model = d;
    c.camera.distortion = std::move(k);
    c.camera.T_B_C = Eigen::Translation3d(tx, -0.064676986768, 0.00981073058949) *
                     Eigen::AngleAxisd(1.5707, Eigen::Vector3d(0.1, 0.2, 0.97).normalized());
    c.has_T_imu_cam = true;
    c.time_offset_s = 0.0031;
    return c;
  };
  const std::vector<double> radtan = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  const std::vector<double> kb4 = {0.0034823894, 0.0007150348, -0.0020532361, 0.0002029367};
  if (tool == "kalibr") {
    rig.cameras = {camera(ProjectionModel::kPinhole, {}, DistortionModel::kRadialTangential, radtan, -0.02),
                   camera(ProjectionModel::kUnified, {0.91}, DistortionModel::kRadialTangential, radtan, 0.05),
                   camera(ProjectionModel::kDoubleSphere, {-0.24, 0.567}, DistortionModel::kNone, {0, 0, 0, 0}, 0.1),
                   camera(ProjectionModel::kExtendedUnified, {0.59, 1.13}, DistortionModel::kNone, {0, 0, 0, 0}, 0.2)};
  } else if (tool == "openvins") {
    rig.cameras = {camera(ProjectionModel::kPinhole, {}, DistortionModel::kRadialTangential, radtan, -0.02),
                   camera(ProjectionModel::kPinhole, {}, DistortionModel::kEquidistant, kb4, 0.09)};
  } else if (tool == "vins") {
    rig.cameras = {camera(ProjectionModel::kPinhole, {}, DistortionModel::kEquidistant, kb4, -0.02),
                   camera(ProjectionModel::kUnified, {2.5}, DistortionModel::kRadialTangential, radtan, 0.09)};
  } else {
    rig.cameras = {camera(ProjectionModel::kDoubleSphere, {-0.24, 0.567}, DistortionModel::kNone, {0, 0, 0, 0}, -0.02),
                   camera(ProjectionModel::kExtendedUnified, {0.59, 1.13}, DistortionModel::kNone, {0, 0, 0, 0}, 0.09),
                   camera(ProjectionModel::kPinhole, {}, DistortionModel::kEquidistant, kb4, 0.2)};
  }
  rig.has_imu = true;
  rig.imu.noise.accel_noise_density = 2.0000e-3;
  rig.imu.noise.accel_random_walk = 3.0000e-3;
  rig.imu.noise.gyro_noise_density = 1.6968e-04;
  rig.imu.noise.gyro_random_walk = 1.9393e-05;
  rig.imu.noise.rate_hz = 200;
  if (tool == "basalt") {  // Basalt's model: a lower-triangular accelerometer scale, a full gyroscope one
    Eigen::Matrix3d Sa, Sg;
    Sa << 0.01, 0, 0, 0.002, -0.01, 0, 0.003, 0.001, 0.02;
    Sg << 0.004, 0.001, -0.002, 0.003, -0.005, 0.001, 0.002, 0.0005, 0.006;
    rig.imu.intrinsics.Ta = (Eigen::Matrix3d::Identity() + Sa).inverse();
    rig.imu.intrinsics.Tw = (Eigen::Matrix3d::Identity() + Sg).inverse();
  }
  if (tool == "kalibr" || tool == "openvins") {
    rig.imu.intrinsics.Tw << 1.01, 0, 0, 0.002, 0.99, 0, -0.001, 0.003, 1.02;
    rig.imu.intrinsics.Tg << 0, 0.001, 0, 0, 0, 0.002, 0.0005, 0, 0;
    rig.imu.intrinsics.Ta << 0.98, 0, 0, 0.001, 1.01, 0, 0.002, -0.001, 1.0;
    rig.imu.intrinsics.R_imu_gyro = Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.3, 0.4, 0.5).normalized()).toRotationMatrix();
  }
  return rig;
}

void expectSame(const RigCalibration& a, const RigCalibration& b, const std::string& tool) {
  SCOPED_TRACE(tool);
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    const CameraCalibration &x = a.cameras[i].camera, &y = b.cameras[i].camera;
    EXPECT_EQ(x.projection, y.projection) << i;
    ASSERT_EQ(x.projection_params.size(), y.projection_params.size()) << i;
    for (size_t k = 0; k < x.projection_params.size(); ++k) EXPECT_NEAR(x.projection_params[k], y.projection_params[k], 1e-9);
    EXPECT_EQ(x.distortion_model, y.distortion_model) << i;
    for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(x.distortion[k], y.distortion[k], 1e-9) << i;
    EXPECT_NEAR(x.fx, y.fx, 1e-9);
    EXPECT_NEAR(x.fy, y.fy, 1e-9);
    EXPECT_NEAR(x.cx, y.cx, 1e-9);
    EXPECT_NEAR(x.cy, y.cy, 1e-9);
    EXPECT_EQ(x.width, y.width);
    EXPECT_EQ(x.height, y.height);
    EXPECT_LT((x.T_B_C.matrix() - y.T_B_C.matrix()).cwiseAbs().maxCoeff(), 1e-9) << i;
    EXPECT_NEAR(a.cameras[i].time_offset_s, b.cameras[i].time_offset_s, 1e-9);
  }
  ASSERT_EQ(a.has_imu, b.has_imu);
  const ImuNoise &m = a.imu.noise, &n = b.imu.noise;
  EXPECT_NEAR(m.accel_noise_density, n.accel_noise_density, 1e-12);
  EXPECT_NEAR(m.accel_random_walk, n.accel_random_walk, 1e-12);
  EXPECT_NEAR(m.gyro_noise_density, n.gyro_noise_density, 1e-12);
  EXPECT_NEAR(m.gyro_random_walk, n.gyro_random_walk, 1e-12);
  const ImuIntrinsics &p = a.imu.intrinsics, &q = b.imu.intrinsics;
  EXPECT_LT((p.Tw - q.Tw).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((p.Tg - q.Tg).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((p.Ta - q.Ta).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((p.R_imu_gyro - q.R_imu_gyro).cwiseAbs().maxCoeff(), 1e-9);
}

// read -> write -> read equal to 1e-9 for every writer (what `adugs calib convert` writes).
TEST(CalibrationFiles, EveryWriterRoundTrips) {
  for (const std::string& tool : calibrationWriterNames()) {
    TempDir dir;
    const RigCalibration rig = rigFor(tool);
    std::vector<std::string> paths;
    for (const auto& [name, text] : formatCalibration(rig, tool)) {
      writeText(dir / name, text);
      paths.push_back((dir / name).string());
    }
    RigCalibration back = readCalibrationFiles({paths.front()});
    for (size_t i = 1; i < paths.size(); ++i) {  // the other files, unless the first names them (VINS)
      if (tool == "vins") break;
      readCalibrationText(test::readFile(paths[i]), paths[i], back);
    }
    if (back.imu.noise_per_sample) resolvePerSampleNoise(back.imu, 200);
    expectSame(rig, back, tool);
    EXPECT_TRUE(back.ignored_keys.empty() || tool == "vins" || tool == "basalt")
        << tool << ": " << back.ignored_keys.front();
  }
}

TEST(CalibrationFiles, WritersRefuseWhatTheirToolCannotHold) {
  RigCalibration ds = rigFor("basalt");
  auto refused = [](const RigCalibration& rig, const std::string& tool) {
    try {
      formatCalibration(rig, tool);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused(ds, "openvins").find("OpenVINS has pinhole cameras"), std::string::npos);
  ds.cameras.resize(1);
  ds.imu.intrinsics = ImuIntrinsics{};
  EXPECT_NE(refused(ds, "vins").find("VINS has no ds camera"), std::string::npos) << refused(ds, "vins");
  RigCalibration mei = rigFor("kalibr");
  mei.imu.intrinsics = ImuIntrinsics{};
  mei.cameras.erase(mei.cameras.begin());
  EXPECT_NE(refused(mei, "basalt").find("Basalt has no omni camera"), std::string::npos) << refused(mei, "basalt");
  EXPECT_NE(refused(rigFor("kalibr"), "basalt").find("Basalt's IMU model"), std::string::npos);
  RigCalibration vins = rigFor("vins");
  vins.imu.noise_per_sample = true;
  EXPECT_NE(refused(vins, "kalibr").find("--imu-rate"), std::string::npos);
  RigCalibration no_imu = rigFor("kalibr");
  no_imu.has_imu = false;
  EXPECT_NE(refused(no_imu, "kalibr").find("no IMU"), std::string::npos);
}

TEST(CalibrationFiles, ShowJsonHasTheDocumentedLayout) {
  RigCalibration rig = rigFor("kalibr");
  rig.ignored_keys = {"a.yaml: cam0.cam_overlaps"};
  const YAML::Node j = loadYamlString(formatCalibrationJson(rig), "show.json");
  ASSERT_TRUE(j["cameras"].IsSequence());
  ASSERT_EQ(j["cameras"].size(), 4u);
  const YAML::Node c0 = j["cameras"][0];
  EXPECT_EQ(c0["model"].as<std::string>(), "pinhole");
  EXPECT_EQ(c0["distortion_model"].as<std::string>(), "radtan");
  EXPECT_EQ(c0["intrinsics"][0].as<double>(), 458.654321);
  EXPECT_EQ(c0["resolution"][1].as<int>(), 480);
  EXPECT_NEAR(c0["T_imu_cam"][0][3].as<double>(), rig.cameras[0].camera.T_B_C(0, 3), 1e-15);
  EXPECT_EQ(c0["T_imu_cam"][3][3].as<double>(), 1.0);
  EXPECT_EQ(c0["time_offset_s"].as<double>(), 0.0031);
  EXPECT_EQ(j["cameras"][1]["model"].as<std::string>(), "mei");
  EXPECT_EQ(j["cameras"][1]["intrinsics"][4].as<double>(), 0.91);  // xi after fx fy cx cy
  EXPECT_EQ(j["cameras"][2]["model"].as<std::string>(), "ds");
  EXPECT_EQ(j["cameras"][2]["intrinsics"].size(), 6u);
  EXPECT_EQ(j["cameras"][2]["distortion_model"].as<std::string>(), "none");
  EXPECT_EQ(j["cameras"][3]["model"].as<std::string>(), "eucm");
  EXPECT_EQ(j["imu"]["gyroscope_random_walk"].as<double>(), 1.9393e-05);
  EXPECT_EQ(j["imu"]["update_rate_hz"].as<double>(), 200.0);
  EXPECT_EQ(j["ignored_keys"][0].as<std::string>(), "a.yaml: cam0.cam_overlaps");
}

}  // namespace
}  // namespace adugs::data
