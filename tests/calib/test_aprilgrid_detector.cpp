#include "calib/target/aprilgrid_detector.h"

#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include <visp3/core/vpImage.h>
#include <visp3/detection/vpDetectorAprilTag.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/target/aprilgrid_render.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

// A rendered board seen through a known homography (with perspective), blurred like a lens.
struct WarpedBoard {
  cv::Mat image;
  std::map<std::pair<int, int>, Eigen::Vector2d> truth;  // (tag, corner) -> pixel
};

// The resolution puts every printed edge on a pixel boundary (no rounding in the truth).
WarpedBoard warpedBoard(const AprilGrid& grid, double angle_deg) {
  const RenderedTarget r = renderAprilGridPxPerM(grid, 2500, 0.02);
  cv::Mat src;
  cv::GaussianBlur(r.image, src, cv::Size(0, 0), 2.0);
  // Board pixel -> image pixel: rotate and scale about the centres, then a perspective tilt.
  const double a = angle_deg * CV_PI / 180, s = 640.0 / std::max(src.cols, src.rows);
  const cv::Matx33d to_origin(1, 0, -src.cols / 2.0, 0, 1, -src.rows / 2.0, 0, 0, 1);
  const cv::Matx33d rotate(s * std::cos(a), -s * std::sin(a), 0, s * std::sin(a),
                           s * std::cos(a), 0, 0, 0, 1);
  const cv::Matx33d tilt(1, 0, 0, 0, 1, 0, 0.00025, 0.00012, 1);
  const cv::Matx33d to_image(1, 0, 550, 0, 1, 480, 0, 0, 1);
  const cv::Matx33d S = to_image * tilt * rotate * to_origin;
  WarpedBoard w;
  cv::warpPerspective(src, w.image, cv::Mat(S), cv::Size(1100, 960), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(255));
  for (int id = 0; id < grid.numTags(); ++id)
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d p = r.pixelOf(grid.corner(id, k));
      const cv::Vec3d q = S * cv::Vec3d(p.x(), p.y(), 1.0);
      w.truth[{id, k}] = Eigen::Vector2d(q[0] / q[2], q[1] / q[2]);
    }
  return w;
}

void expectAllCornersAtTruth(const AprilGrid& grid, double angle_deg) {
  const WarpedBoard w = warpedBoard(grid, angle_deg);
  AprilGridDetector detector(grid);
  DetectionStats stats;
  const TargetObservation obs = detector.detect(w.image, 0, &stats);
  ASSERT_EQ(static_cast<int>(obs.corners.size()), 4 * grid.numTags())
      << "border " << grid.border_bits << ": kept " << stats.kept_tags << " of raw "
      << stats.raw_tags << ", subpix " << stats.rejected_subpix << ", inconsistent "
      << stats.rejected_inconsistent;
  double worst = 0;
  for (const auto& c : obs.corners) {
    const double err = (c.pixel - w.truth.at({c.tag_id, c.corner})).norm();
    worst = std::max(worst, err);
    EXPECT_TRUE(c.point.isApprox(grid.corner(c.tag_id, c.corner)));
  }
  EXPECT_LT(worst, 0.3) << "border " << grid.border_bits << " angle " << angle_deg;
}

// The rendered Kalibr board (2-bit border, system apriltag backend) comes back with every id at
// its place and every corner in Kalibr's numbering, for several in-plane rotations (a wrong
// corner mapping shows up as errors of a tag side).
TEST(AprilGridDetector, RenderedKalibrBoardThroughAHomography) {
  AprilGrid grid;
  grid.tag_rows = 5;
  grid.tag_cols = 6;
  for (double angle : {0.0, 35.0, 180.0, -100.0}) expectAllCornersAtTruth(grid, angle);
}

// The same with standard 1-bit tags.
TEST(AprilGridDetector, RenderedStandardBoard) {
  AprilGrid grid;
  grid.tag_rows = 4;
  grid.tag_cols = 5;
  grid.tag_size_m = 0.08;  // 8 bits of 1 cm: edges on pixel boundaries at 2500 px/m
  grid.border_bits = 1;
  for (double angle : {0.0, 120.0}) expectAllCornersAtTruth(grid, angle);
}

// The real EuRoC AprilGrid photo: all 36 tags, and the corners (labelled with our corner
// numbering and target points) must fit EuRoC's published cam0 calibration with a rigid pose.
// A wrong corner order or a mirrored target frame cannot.
TEST(AprilGridDetector, RealEurocImageFitsPublishedCalibration) {
  const auto path = test::sharedDataDir() / "euroc_calib_aprilgrid" / "stereo" /
                    "cam0_1403709395937837056.png";
  ADUGS_REQUIRE_SHARED(path);
  const cv::Mat gray = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(gray.cols, 752);
  AprilGridDetector detector(AprilGrid{});
  DetectionStats stats;
  const TargetObservation obs = detector.detect(gray, 0, &stats);
  EXPECT_EQ(stats.kept_tags, 36);
  ASSERT_GE(obs.corners.size(), 100u);

  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const auto& c : obs.corners) {
    object.emplace_back(c.point.x(), c.point.y(), c.point.z());
    image.emplace_back(c.pixel.x(), c.pixel.y());
  }
  const cv::Mat K = (cv::Mat_<double>(3, 3) << 458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 4) << -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05);
  cv::Mat rvec, tvec;
  ASSERT_TRUE(cv::solvePnP(object, image, K, D, rvec, tvec, false, cv::SOLVEPNP_IPPE));
  cv::solvePnPRefineLM(object, image, K, D, rvec, tvec);
  std::vector<cv::Point2d> projected;
  cv::projectPoints(object, rvec, tvec, K, D, projected);
  double sum2 = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const cv::Point2d d = projected[i] - image[i];
    sum2 += d.dot(d);
  }
  const double rms = std::sqrt(sum2 / image.size());
  EXPECT_LT(rms, 0.5) << "corner numbering does not fit the real camera";
  // The board is in front of the camera and its z axis (out of the printed side) faces it.
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  EXPECT_GT(tvec.at<double>(2), 0.3);
  EXPECT_LT(R.at<double>(2, 2), 0.0);
}

// ViSP's own AprilTag photo (visp-images-data), standard 36h11 tags, with its ground truth.
TEST(AprilGridDetector, VispAprilTagPhotoMatchesItsGroundTruth) {
  const std::string dir = "/usr/share/visp-images-data/ViSP-images/AprilTag/";
  ADUGS_REQUIRE_SHARED(dir + "AprilTag.pgm");
  std::ifstream gt(dir + "ground_truth_detection.txt");
  std::map<int, std::array<Eigen::Vector2d, 4>> truth;
  std::string label;
  while (gt >> label) {
    const int id = std::stoi(label.substr(label.rfind('_') + 1));
    for (int k = 0; k < 4; ++k) {
      double v, u;  // the file lists row, column
      gt >> v >> u;
      truth[id][k] = {u, v};
    }
  }
  ASSERT_GE(truth.size(), 5u);
  const cv::Mat gray = cv::imread(dir + "AprilTag.pgm", cv::IMREAD_GRAYSCALE);
  AprilGrid standard;
  standard.border_bits = 1;
  AprilGridDetector detector(standard);
  const std::vector<TagDetection> tags = detector.detectTags(gray);
  int matched = 0;
  for (const auto& t : tags) {
    auto it = truth.find(t.id);
    if (it == truth.end()) continue;
    for (int k = 0; k < 4; ++k) EXPECT_LT((t.corners[k] - it->second[k]).norm(), 0.5) << t.id;
    ++matched;
  }
  EXPECT_EQ(matched, static_cast<int>(truth.size()));
}

// The product calls the AprilTag library directly for standard tags too (ViSP's detection module
// would load OpenCV's image codecs into every process); ViSP's vpDetectorAprilTag, which it used
// before, is the oracle: the same tags with the same corners on ViSP's photo.
TEST(AprilGridDetector, StandardTagsAsViSPDetectsThem) {
  const std::string path = "/usr/share/visp-images-data/ViSP-images/AprilTag/AprilTag.pgm";
  ADUGS_REQUIRE_SHARED(path);
  const cv::Mat gray = cv::imread(path, cv::IMREAD_GRAYSCALE);
  vpImage<unsigned char> image(static_cast<unsigned>(gray.rows), static_cast<unsigned>(gray.cols));
  for (int r = 0; r < gray.rows; ++r) std::copy(gray.ptr<uint8_t>(r), gray.ptr<uint8_t>(r) + gray.cols, image[r]);
  vpDetectorAprilTag visp(vpDetectorAprilTag::TAG_36h11);
  visp.detect(image);
  std::map<int, std::vector<vpImagePoint>> expected;
  for (size_t i = 0; i < visp.getNbObjects(); ++i) expected[visp.getTagsId()[i]] = visp.getPolygon(i);
  ASSERT_GE(expected.size(), 5u);

  AprilGrid standard;
  standard.border_bits = 1;
  const std::vector<TagDetection> tags = AprilGridDetector(standard).detectTags(gray);
  ASSERT_EQ(tags.size(), expected.size());
  double worst = 0;
  for (const TagDetection& t : tags) {
    ASSERT_EQ(expected.count(t.id), 1u) << "id " << t.id << " not found by ViSP";
    for (int k = 0; k < 4; ++k)
      worst = std::max(worst, (t.corners[k] - Eigen::Vector2d(expected[t.id][k].get_u(), expected[t.id][k].get_v())).norm());
  }
  EXPECT_LT(worst, 0.01) << "px";
}

std::vector<TagDetection> projectedTags(const AprilGrid& grid, const cv::Matx33d& H) {
  std::vector<TagDetection> tags;
  for (int id = 0; id < grid.numTags(); ++id) {
    TagDetection t;
    t.id = id;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p = grid.corner(id, k);
      const cv::Vec3d q = H * cv::Vec3d(p.x(), p.y(), 1);
      t.corners[k] = {q[0] / q[2], q[1] / q[2]};
    }
    tags.push_back(t);
  }
  return tags;
}

TEST(AprilGridDetector, RejectsTagsThatDoNotFitTheirNeighbours) {
  AprilGrid grid;
  const cv::Matx33d H(2000, 100, 100, -80, -1900, 900, 0.1, 0.2, 1);
  auto tags = projectedTags(grid, H);
  EXPECT_EQ(rejectInconsistentTags(grid, tags, 0.15), 0);
  ASSERT_EQ(tags.size(), 36u);
  // Tag 14 read with its corners rotated by one (wrong orientation), tag 20 misread as 23.
  std::rotate(tags[14].corners.begin(), tags[14].corners.begin() + 1, tags[14].corners.end());
  tags[20].id = 23;
  tags.erase(tags.begin() + 23);
  EXPECT_EQ(rejectInconsistentTags(grid, tags, 0.15), 2);
  for (const auto& t : tags) {
    EXPECT_NE(t.id, 14);
    EXPECT_NE(t.id, 23);
  }
  EXPECT_EQ(tags.size(), 33u);
  // An isolated tag cannot be verified.
  std::vector<TagDetection> lonely = {projectedTags(grid, H)[0], projectedTags(grid, H)[35]};
  EXPECT_EQ(rejectInconsistentTags(grid, lonely, 0.15), 2);
}

TEST(AprilGridDetector, RejectsIdsOutsideTheGridAndDuplicates) {
  AprilGrid printed;  // 6x6 on paper
  const RenderedTarget r = renderAprilGridPxPerM(printed, 1250, 0.02);
  cv::Mat blurred;
  cv::GaussianBlur(r.image, blurred, cv::Size(0, 0), 1.0);
  // Configured as a 3x6 grid: tags 18..35 are not part of it.
  AprilGrid configured = printed;
  configured.tag_rows = 3;
  AprilGridDetector small(configured);
  DetectionStats stats;
  TargetObservation obs = small.detect(blurred, 0, &stats);
  EXPECT_EQ(stats.rejected_id, 18);
  EXPECT_EQ(stats.kept_tags, 18);
  // Two copies of the board side by side: every id is seen twice, none can be trusted.
  cv::Mat twice;
  cv::hconcat(blurred, blurred, twice);
  AprilGridDetector full(printed);
  obs = full.detect(twice, 0, &stats);
  EXPECT_TRUE(obs.corners.empty());
  EXPECT_GE(stats.rejected_duplicate, 64);  // a tag missed in one copy is not a duplicate
  EXPECT_EQ(stats.rejected_duplicate % 2, 0);
}

}  // namespace
}  // namespace adugs::calib
