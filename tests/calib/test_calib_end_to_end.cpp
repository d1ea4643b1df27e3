// Images -> detection -> intrinsics: the rendered Kalibr board seen through a known distorted
// camera (ray-traced per pixel with cv::remap), written as an image folder and calibrated with
// `adugs calib intrinsics --images`, and in-process through the library.
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include "calib/intrinsics/intrinsics_calibrator.h"
#include "calib/target/aprilgrid_detector.h"
#include "calib/target/aprilgrid_render.h"
#include "calib/target/aprilgrid_target_yaml.h"
#include "data/input_error.h"
#include "data/sources/image_source.h"
#include "tests/calib/synthetic_views.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {
namespace fs = std::filesystem;

// The ray of every pixel (z = 1; NaN where unprojection fails), shared by all views.
std::vector<Eigen::Vector3d> pixelRays(const CalibCamera& cam) {
  std::vector<Eigen::Vector3d> rays(static_cast<size_t>(cam.width * cam.height));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u)
      if (!cam.unproject({double(u), double(v)}, rays[static_cast<size_t>(v * cam.width + u)]))
        rays[static_cast<size_t>(v * cam.width + u)].setConstant(NAN);
  return rays;
}

// One image of the board from camera pose T_T_C (camera -> target).
cv::Mat renderView(const CalibCamera& cam, const std::vector<Eigen::Vector3d>& rays,
                   const RenderedTarget& board, const Eigen::Isometry3d& T_T_C) {
  cv::Mat map_x(cam.height, cam.width, CV_32FC1), map_y(cam.height, cam.width, CV_32FC1);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d& ray = rays[static_cast<size_t>(v * cam.width + u)];
      float bx = -1, by = -1;
      if (ray.allFinite()) {
        const Eigen::Vector3d o = T_T_C.translation(), d = T_T_C.linear() * ray;
        if (std::abs(d.z()) > 1e-9) {
          const double s = -o.z() / d.z();
          if (s > 0) {
            const Eigen::Vector2d px = board.pixelOf(o + s * d);
            bx = float(px.x());
            by = float(px.y());
          }
        }
      }
      map_x.at<float>(v, u) = bx;
      map_y.at<float>(v, u) = by;
    }
  cv::Mat image;
  cv::remap(board.image, image, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(255));
  // A little sensor blur and noise.
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.7);
  cv::Mat noise(image.size(), CV_16SC1);
  cv::randn(noise, 0, 2);
  image.convertTo(image, CV_16SC1);
  image += noise;
  image.convertTo(image, CV_8UC1);
  return image;
}

std::vector<Eigen::Isometry3d> cameraPoses(const AprilGrid& grid, int n) {
  std::vector<Eigen::Isometry3d> poses;
  const Eigen::Vector3d centre(grid.tag_cols * grid.pitch() / 2, grid.tag_rows * grid.pitch() / 2, 0);
  for (int i = 0; i < n; ++i) {
    const double pan = 0.5 * std::sin(1.7 * i), tilt = 0.45 * std::cos(2.3 * i);
    const double dist = 0.75 + 0.25 * std::sin(0.9 * i);
    const Eigen::Vector3d eye =
        centre + dist * Eigen::Vector3d(std::sin(pan), std::sin(tilt), std::cos(pan) * std::cos(tilt));
    const Eigen::Vector3d z = (centre - eye).normalized();
    const Eigen::Vector3d up = Eigen::AngleAxisd(0.3 * std::sin(1.1 * i), z) * Eigen::Vector3d(0, 1, 0);
    const Eigen::Vector3d x = up.cross(z).normalized();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() << x, z.cross(x), z;
    T.translation() = eye;
    poses.push_back(T);
  }
  return poses;
}

TEST(CalibEndToEnd, RenderedImagesThroughTheCliRecoverTheCamera) {
  const CalibCamera truth = synth::eurocLikeCamera();
  const AprilGrid grid;  // Kalibr 6x6, 2-bit border
  const RenderedTarget board = renderAprilGridPxPerM(grid, 2500, 0.02);
  test::TempDir tmp("adugs_calib_e2e");
  fs::create_directories(tmp / "images");
  const auto poses = cameraPoses(grid, 10);
  const auto rays = pixelRays(truth);
  for (size_t i = 0; i < poses.size(); ++i) {
    char name[64];
    std::snprintf(name, sizeof(name), "frame_%03zu.png", i);
    cv::imwrite((tmp / "images" / name).string(), renderView(truth, rays, board, poses[i]));
  }
  test::writeText(tmp / "target.yaml", formatAprilGridYaml(grid));

  // In-process: detection on every image finds most of the board.
  data::ImageSource source((tmp / "images").string());
  EXPECT_EQ(source.kind(), "folder");
  AprilGridDetector detector(grid);
  std::vector<TargetObservation> views;
  data::ImageFrame frame;
  while (source.next(frame)) views.push_back(detector.detect(frame.gray, frame.t_ns));
  ASSERT_EQ(views.size(), poses.size());
  EXPECT_EQ(views[3].t_ns, 3000000000LL);  // names without a timestamp: 1 s apart
  size_t corners = 0;
  for (const auto& v : views) corners += v.corners.size();
  EXPECT_GT(corners, 0.8 * 144 * views.size());
  const IntrinsicsResult r = calibrateIntrinsics(views, truth.width, truth.height, {});
  std::printf("end-to-end: fu %.3f fv %.3f pu %.3f pv %.3f (truth 458.654 457.296 367.215 "
              "248.375), rms %.3f px, %d corners, %d outliers\n",
              r.camera.fu(), r.camera.fv(), r.camera.pu(), r.camera.pv(), r.rms_px,
              r.corners_used, r.outliers);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(r.camera.params[i], truth.params[i], 0.002 * truth.params[i]) << i;
  EXPECT_LT(r.rms_px, 0.3);

  // The same through the command line.
  if (!fs::exists(ADUGS_BINARY)) ADUGS_SKIP_OR_FAIL("adugs not built at " << ADUGS_BINARY);
  std::string out;
  ASSERT_EQ(test::runAdugs("calib intrinsics --target " + (tmp / "target.yaml").string() +
                               " --images " + (tmp / "images").string() + " --out " +
                               (tmp / "out").string() + " --save-corners",
                           &out),
            0)
      << out;
  const YAML::Node cam = YAML::LoadFile((tmp / "out" / "camchain.yaml").string())["cam0"];
  EXPECT_NEAR(cam["intrinsics"][0].as<double>(), truth.fu(), 0.002 * truth.fu());
  EXPECT_EQ(cam["resolution"][0].as<int>(), 752);
  EXPECT_TRUE(fs::exists(tmp / "out" / "corners" / "0.csv"));
}

TEST(ImageSource, ReadsAnEurocCameraFolder) {
  const auto euroc = test::sharedDataDir() / "euroc_v101_micro" / "mav0" / "cam0";
  ADUGS_REQUIRE_SHARED(euroc);
  data::ImageSource s(euroc.string(), 10);
  EXPECT_EQ(s.kind(), "euroc");
  EXPECT_EQ(s.sizeHint(), 10u);
  data::ImageFrame f;
  ASSERT_TRUE(s.next(f));
  EXPECT_EQ(f.gray.cols, 752);
  EXPECT_GT(f.t_ns, 1400000000000000000LL);
}

TEST(ImageSource, AMissingFolderIsAnInputError) {
  EXPECT_THROW(data::ImageSource("/nonexistent/folder"), data::InputError);
}

TEST(ImageSource, ReadsAVideo) {
  ADUGS_REQUIRE_PEDESTRIAN_VIDEO();
  const std::string& video = test::kPedestrianVideo;
  data::ImageSource s(video, 100);
  EXPECT_EQ(s.kind(), "video");
  EXPECT_EQ(s.sizeHint(), 7u);  // 795 frames
  data::ImageFrame f;
  ASSERT_TRUE(s.next(f));
  EXPECT_EQ(f.gray.type(), CV_8UC1);
  EXPECT_EQ(f.t_ns, 0);
  ASSERT_TRUE(s.next(f));
  EXPECT_EQ(f.name, video + "#100");
  EXPECT_EQ(f.t_ns, 10'000'000'000LL);  // 10 frames per second: each frame's own stream time
}

}  // namespace
}  // namespace adugs::calib
