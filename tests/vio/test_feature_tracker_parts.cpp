// The front-end's pieces: RANSAC outlier rejection, the ORB-equivalent corner detector, options
// from YAML, and the overlay picture.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "data/input_error.h"
#include "tests/test_support.h"
#include "vio/frontend/feature_detector.h"
#include "vio/frontend/feature_overlay.h"
#include "vio/frontend/feature_ransac.h"
#include "vio/frontend/feature_tracker_options.h"

namespace adugs::vio {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Two views of random 3-D points with a real baseline; 20 of 150 correspondences are pushed 6 px
// across their epipolar line, everyone gets 0.2 px noise.
TEST(FeatureRansac, RejectsInjectedOutliers) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3, 3), depth(4, 10);
  std::normal_distribution<double> noise(0, 0.2 / 460);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Vector3d t(0.4, 0.1, 0.15);  // p_C2 = R p_C1 + t
  const Eigen::Matrix3d E = skew(t) * R;    // x2^T E x1 = 0
  std::vector<Eigen::Vector2d> a, b;
  std::vector<bool> outlier;
  for (int i = 0; i < 150; ++i) {
    const Eigen::Vector3d p1(u(rng), u(rng) * 0.6, depth(rng));
    const Eigen::Vector3d p2 = R * p1 + t;
    Eigen::Vector2d x1 = p1.head<2>() / p1.z(), x2 = p2.head<2>() / p2.z();
    const bool bad = i % 7 == 3 && i < 140;
    if (bad) {
      const Eigen::Vector3d line = E * x1.homogeneous();
      x2 += (6.0 / 460) * line.head<2>().normalized();
    }
    x1 += Eigen::Vector2d(noise(rng), noise(rng));
    x2 += Eigen::Vector2d(noise(rng), noise(rng));
    a.push_back(x1), b.push_back(x2), outlier.push_back(bad);
  }
  FundamentalRansacOptions o;
  o.focal_px = 460;
  o.threshold_px = 1.0;
  const std::vector<bool> inlier = fundamentalInliers(a, b, o);
  int kept_good = 0, good = 0, kept_bad = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    good += !outlier[i];
    kept_good += !outlier[i] && inlier[i];
    kept_bad += outlier[i] && inlier[i];
  }
  EXPECT_EQ(kept_bad, 0);
  EXPECT_GE(kept_good, 0.95 * good);
}

TEST(FeatureRansac, TooFewPointsKeepsAllAndSizesMustMatch) {
  const std::vector<Eigen::Vector2d> a(5, Eigen::Vector2d(0.1, 0.2)), b(5, Eigen::Vector2d(0.3, 0));
  EXPECT_EQ(fundamentalInliers(a, b, {}), std::vector<bool>(5, true));
  EXPECT_THROW(fundamentalInliers(a, {}, {}), std::invalid_argument);
}

TEST(FeatureDetector, SameCornersAsOrbFirstLevel) {
  const auto path =
      test::sharedDataDir() / "euroc_v101_micro/mav0/cam0/data/1403715273262142976.png";
  ADUGS_REQUIRE_SHARED(path);
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  cv::Mat mask(image.size(), CV_8UC1, cv::Scalar(255));
  mask(cv::Rect(300, 200, 200, 150)).setTo(0);
  FeatureTrackerOptions o;
  o.max_candidates = 400;
  std::vector<cv::KeyPoint> ours, orb;
  detectOrbCorners(image, mask, o, &ours);
  cv::ORB::create(o.max_candidates, 1.2f, 1, o.detection_border_px, 0, 2, cv::ORB::FAST_SCORE, 31,
                  o.fast_threshold)
      ->detect(image, orb, mask);
  ASSERT_EQ(ours.size(), orb.size());
  auto key = [](const cv::KeyPoint& k) { return std::make_tuple(k.pt.x, k.pt.y, k.response); };
  auto less = [&](const cv::KeyPoint& x, const cv::KeyPoint& y) { return key(x) < key(y); };
  std::sort(ours.begin(), ours.end(), less);
  std::sort(orb.begin(), orb.end(), less);
  for (size_t i = 0; i < ours.size(); ++i) EXPECT_EQ(key(ours[i]), key(orb[i])) << i;
}

TEST(FeatureTrackerOptions, YamlOverridesDefaultsAndRejectsUnknownKeys) {
  const FeatureTrackerOptions o = parseFeatureTrackerOptions(
      "max_features: 150\nmin_distance_px: 25.5\nfb_check: false\nklt_pyramid_levels: 2\n",
      "fe.yaml");
  EXPECT_EQ(o.max_features, 150);
  EXPECT_DOUBLE_EQ(o.min_distance_px, 25.5);
  EXPECT_FALSE(o.fb_check);
  EXPECT_EQ(o.klt_pyramid_levels, 2);
  EXPECT_EQ(o.klt_window_px, FeatureTrackerOptions{}.klt_window_px);  // untouched default
  EXPECT_THROW(parseFeatureTrackerOptions("max_feature: 150\n", "fe.yaml"), data::InputError);
  EXPECT_THROW(parseFeatureTrackerOptions("max_features: 0\n", "fe.yaml"), data::InputError);
  EXPECT_THROW(parseFeatureTrackerOptions("fb_threshold_px: fast\n", "fe.yaml"), data::InputError);
  const FeatureTrackerOptions a = parseFeatureTrackerOptions(
      "anchor_alignment: false\nanchor_patch_half_px: 6\nanchor_min_zncc: 0.8\n", "fe.yaml");
  EXPECT_FALSE(a.anchor_alignment);
  EXPECT_EQ(a.anchor_patch_half_px, 6);
  EXPECT_DOUBLE_EQ(a.anchor_min_zncc, 0.8);
  EXPECT_THROW(parseFeatureTrackerOptions("anchor_patch_half_px: 1\n", "fe.yaml"), data::InputError);
  EXPECT_THROW(parseFeatureTrackerOptions("anchor_max_scale: 0.5\n", "fe.yaml"), data::InputError);
  try {
    parseFeatureTrackerOptions("ransac: true\nklt_window_px: 1\n", "fe.yaml");
    FAIL();
  } catch (const data::InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("klt_window_px"), std::string::npos);
  }
}

TEST(FeatureOverlay, DrawsTracksMaskAndDrops) {
  cv::Mat image(100, 120, CV_8UC1, cv::Scalar(100));
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  mask(cv::Rect(80, 60, 30, 30)).setTo(255);
  FrameFeatures f;
  f.ids = {1, 2};
  f.pixels = {{20, 20}, {50, 30}};
  f.prev_pixels = {{15, 20}, {50, 30}};
  f.track_counts = {40, 1};
  const cv::Mat out = drawFeatureOverlay(image, f, mask, {{95, 75}}, {{60, 80}});
  ASSERT_EQ(out.type(), CV_8UC3);
  ASSERT_EQ(out.size(), image.size());
  EXPECT_EQ(out.at<cv::Vec3b>(20, 20), cv::Vec3b(0, 0, 255));  // old track: red
  EXPECT_EQ(out.at<cv::Vec3b>(30, 50), cv::Vec3b(255, 0, 0));  // new point: blue
  const cv::Vec3b tint = out.at<cv::Vec3b>(62, 82);            // masked: red tinted
  EXPECT_GT(tint[2], tint[0]);
  EXPECT_EQ(out.at<cv::Vec3b>(5, 5), cv::Vec3b(100, 100, 100));  // elsewhere untouched
  EXPECT_THROW(drawFeatureOverlay(cv::Mat(10, 10, CV_32F), f), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::vio
